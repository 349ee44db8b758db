// The emulator's MuJoCo plants (massid_emulator_mujoco) on the example robots.
//
//   Static:        on a platform held still (at home, then tilted 20 deg) with
//                  the joints held, the sensor reads the static gravity wrench
//                  of massid::simulate_wrenches, gravity rotated into the sensor
//                  frame (relative 1e-6).
//   Tracking:      the platform servo follows a 0.05 m / 5 deg, 0.5 Hz sinusoid
//                  commanded at 1 kHz, with the arm moving on it.
//   Free floating: the reference conserves momentum (zero) and keeps its centre
//                  of mass still while the arm moves, and the interface moves.
//   Dynamic load:  with the arm moving on a still platform, the sensor reads
//                  more than the gravity wrench; once stopped, the gravity
//                  wrench again.
//   Emulation:     the admittance model against the reference's own sensor
//                  (open loop), the closed loop with the true gravity model,
//                  and the targets with identified parameters.
//   Mimic joints:  the plant drives a URDF mimic joint with its master: its
//                  sensor reads, at rest and in motion, what massid computes
//                  for the same robot with the mimic tags removed and the
//                  mimic positions set by the test (and what massid computes
//                  for the robot with them); the Panda with its fingers runs
//                  the tests above.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"
#include "massid/core/simulate.hpp"
#include "massid/emulator/emulation.hpp"
#include "massid/emulator/mujoco_plant.hpp"
#include "massid/emulator/spacecraft.hpp"
#include "massid/emulator/stewart_platform.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "mimic_support.hpp"

namespace {

using massid::emulator::FreeFloatingReference;
using massid::emulator::PlantOptions;
using massid::emulator::PlatformPlant;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.001;  // the emulator's control period

struct Robot {
  const char* name;
  const char* urdf;
};

void PrintTo(const Robot& robot, std::ostream* os) { *os << robot.name; }

massid::Model load(const Robot& robot) {
  return massid::load_urdf(std::string(MASSID_SOURCE_DIR) + "/" + robot.urdf);
}

// The static gravity wrench by massid at q, gravity g in the sensor frame.
massid::Wrench static_wrench(const massid::Model& model, const Eigen::VectorXd& q,
                             const Eigen::Vector3d& g_sensor) {
  massid::Samples s;
  s.q = q.transpose();
  s.gravity = g_sensor.transpose();
  s.line = {1};
  return massid::simulate_wrenches(model, s).row(0).transpose();
}

Eigen::Vector3d gravity_in_sensor(const PlatformPlant& plant, const PlantOptions& options) {
  return plant.sensor_pose().linear().transpose() * options.gravity;
}

// A pose with every joint away from zero, different per joint.
Eigen::VectorXd test_pose(const massid::Model& model) {
  Eigen::VectorXd q(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) q[j] = 0.4 + 0.3 * std::sin(1.7 * j + 0.5);
  return q;
}

double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

class Plant : public ::testing::TestWithParam<Robot> {};

TEST_P(Plant, StaticWrenchMatchesSimulateLevelAndTilted) {
  const massid::Model model = load(GetParam());
  const massid::emulator::PlatformGeometry geometry = massid::emulator::default_geometry();
  PlantOptions options;
  // A sensor mounted off the platform origin and turned, to exercise the frames.
  options.platform_T_sensor.translation() = Eigen::Vector3d(0.02, -0.01, 0.05);
  options.platform_T_sensor.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).matrix();
  PlatformPlant plant(model, geometry, options);
  const Eigen::VectorXd q = test_pose(model);
  plant.set_joints(q);
  plant.set_platform_command(geometry.home);
  for (int k = 0; k < 1000; ++k) plant.advance(kDt);

  const auto check = [&](const char* what) {
    const massid::Wrench expected = static_wrench(model, q, gravity_in_sensor(plant, options));
    const massid::Wrench measured = plant.measured_wrench();
    const double rel = (measured - expected).norm() / expected.norm();
    std::cout << "[ plant    ] " << GetParam().name << " " << what << ": |w| " << expected.norm()
              << ", relative difference " << rel << ", joint error "
              << (plant.joint_positions() - q).cwiseAbs().maxCoeff() << " rad\n";
    EXPECT_LT(rel, 1e-6) << what << "\nmeasured " << measured.transpose() << "\nexpected "
                         << expected.transpose();
    EXPECT_GT(expected.head<3>().norm(), 0.9 * model.nominal_total_mass() * 9.80665);
  };
  check("level");
  EXPECT_LT((plant.platform_pose().translation() - geometry.home.translation()).norm(), 1e-9);

  // Tilt 20 deg about a horizontal axis, smoothly over 1 s, then settle 1 s.
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, 0.0).normalized();
  const double tilt = 20.0 * kPi / 180.0;
  for (int k = 1; k <= 2000; ++k) {
    const double u = std::min(1.0, k * kDt / 1.0);
    const double s = u * u * (3.0 - 2.0 * u);
    Eigen::Isometry3d cmd = geometry.home;
    cmd.linear() = Eigen::AngleAxisd(s * tilt, axis).matrix() * geometry.home.linear();
    plant.set_platform_command(cmd);
    plant.advance(kDt);
  }
  EXPECT_NEAR(angle_between(plant.platform_pose().linear(), geometry.home.linear()), tilt, 1e-9);
  check("tilted 20 deg");
}

TEST_P(Plant, PlatformTracksSinusoidWithArmMoving) {
  const massid::Model model = load(GetParam());
  const massid::emulator::PlatformGeometry geometry = massid::emulator::default_geometry();
  const PlantOptions options;
  PlatformPlant plant(model, geometry, options);
  const Eigen::VectorXd q0 = test_pose(model);
  plant.set_joints(q0);
  const double w = 2.0 * kPi * 0.5;
  const Eigen::Vector3d dir = Eigen::Vector3d(1.0, 0.6, 0.4).normalized();
  const Eigen::Vector3d rot_axis = Eigen::Vector3d(0.3, 1.0, 0.5).normalized();
  const auto command = [&](double t) {
    Eigen::Isometry3d cmd = geometry.home;
    cmd.translation() += 0.05 * std::sin(w * t) * dir;
    cmd.linear() = Eigen::AngleAxisd(5.0 * kPi / 180.0 * std::sin(w * t), rot_axis).matrix() *
                   geometry.home.linear();
    return cmd;
  };
  double max_pos = 0.0, max_rot = 0.0;
  const int steps = 3000;
  for (int k = 0; k < steps; ++k) {
    const double t = k * kDt;
    plant.set_platform_command(command(t));
    // The arm swings too, loading the platform.
    Eigen::VectorXd q = q0, qd = Eigen::VectorXd::Zero(model.num_joints());
    const double f = kPi * 0.8;  // sin^2: 0.5 rad swings at 0.8 Hz, starting at rest
    for (int j = 0; j < model.num_joints(); ++j) {
      q[j] += 0.5 * std::sin(f * t) * std::sin(f * t);
      qd[j] = 0.5 * f * std::sin(2.0 * f * t);
    }
    plant.set_joint_command(q, qd);
    plant.advance(kDt);
    if (t < 0.3) continue;  // the start-up transient (the sinusoid starts at full speed)
    const Eigen::Isometry3d target = command(plant.time());
    max_pos =
        std::max(max_pos, (plant.platform_pose().translation() - target.translation()).norm());
    max_rot = std::max(max_rot, angle_between(plant.platform_pose().linear(), target.linear()));
  }
  std::cout << "[ plant    ] " << GetParam().name << " tracking 0.05 m / 5 deg at 0.5 Hz, arm "
            << model.nominal_total_mass() << " kg moving: max error " << max_pos << " m, "
            << max_rot << " rad\n";
  EXPECT_LT(max_pos, 1e-4);
  EXPECT_LT(max_rot, 1e-3);
}

TEST_P(Plant, FreeFloatingReferenceConservesMomentum) {
  const massid::Model model = load(GetParam());
  massid::emulator::SpacecraftParameters sc;
  sc.mass = 60.0;
  sc.inertia << 6.0, 0.2, -0.1, 0.2, 5.0, 0.3, -0.1, 0.3, 4.0;
  sc.body_T_interface.translation() = Eigen::Vector3d(0.1, -0.05, 0.4);
  sc.body_T_interface.linear() =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  Eigen::Isometry3d world_T_interface0 = Eigen::Isometry3d::Identity();
  world_T_interface0.translation() = Eigen::Vector3d(0.2, 0.1, 0.7);
  world_T_interface0.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).matrix();
  FreeFloatingReference ref(model, sc, world_T_interface0);
  EXPECT_LT((ref.interface_pose().matrix() - world_T_interface0.matrix()).cwiseAbs().maxCoeff(),
            1e-12);
  EXPECT_NEAR(ref.total_mass(), sc.mass + model.nominal_total_mass(), 1e-12);
  const Eigen::VectorXd q0 = test_pose(model);
  ref.set_joints(q0);
  const Eigen::Vector3d com0 = ref.center_of_mass();
  const Eigen::Isometry3d pose0 = ref.interface_pose();
  double max_p = 0.0, max_l = 0.0, max_com = 0.0, max_move = 0.0, max_rot = 0.0, max_qd = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const double t = k * kDt;
    // Joint j: 0.6 rad sin^2 swings at 0.3 + 0.1 j Hz, starting at rest.
    Eigen::VectorXd q = q0, qd = Eigen::VectorXd::Zero(model.num_joints());
    for (int j = 0; j < model.num_joints(); ++j) {
      const double f = kPi * (0.3 + 0.1 * j);
      q[j] += 0.6 * std::sin(f * t) * std::sin(f * t);
      qd[j] = 0.6 * f * std::sin(2.0 * f * t);
    }
    ref.set_joint_command(q, qd);
    ref.advance(kDt);
    max_p = std::max(max_p, ref.linear_momentum().norm());
    max_l = std::max(max_l, ref.angular_momentum().norm());
    max_com = std::max(max_com, (ref.center_of_mass() - com0).norm());
    max_move =
        std::max(max_move, (ref.interface_pose().translation() - pose0.translation()).norm());
    max_rot = std::max(max_rot, angle_between(ref.interface_pose().linear(), pose0.linear()));
    max_qd = std::max(max_qd, ref.joint_velocities().cwiseAbs().maxCoeff());
  }
  std::cout << "[ plant    ] " << GetParam().name << " free floating 5 s: max |P| " << max_p
            << " kg m/s, max |L| " << max_l << " kg m^2/s, com drift " << max_com
            << " m; interface moved up to " << max_move << " m, " << max_rot
            << " rad; joint speeds up to " << max_qd << " rad/s\n";
  EXPECT_GT(max_qd, 0.5);
  EXPECT_LT(max_p, 1e-6);
  EXPECT_LT(max_l, 1e-6);
  EXPECT_LT(max_com, 1e-6);
  EXPECT_GT(max_move, 1e-3);
}

TEST_P(Plant, MovingArmLoadsSensorBeyondGravity) {
  const massid::Model model = load(GetParam());
  const massid::emulator::PlatformGeometry geometry = massid::emulator::default_geometry();
  const PlantOptions options;
  PlatformPlant plant(model, geometry, options);
  const Eigen::VectorXd q0 = test_pose(model);
  plant.set_joints(q0);
  double max_dyn = 0.0;
  Eigen::VectorXd q = q0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 2000; ++k) {
    const double t = k * kDt;
    Eigen::VectorXd qd = Eigen::VectorXd::Zero(model.num_joints());
    if (t < 1.5) {
      const double f = kPi;  // sin^2: 0.5 rad swings at 1 Hz, from rest to rest
      for (int j = 0; j < model.num_joints(); ++j) {
        q[j] = q0[j] + 0.5 * std::sin(f * t) * std::sin(f * t);
        qd[j] = 0.5 * f * std::sin(2.0 * f * t);
      }
    }
    plant.set_joint_command(q, qd);
    plant.advance(kDt);
    if (t < 1.5) {
      const massid::Wrench gravity =
          static_wrench(model, plant.joint_positions(), gravity_in_sensor(plant, options));
      max_dyn = std::max(max_dyn, (plant.measured_wrench() - gravity).head<3>().norm());
    }
  }
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
      2000.0;
  // Stopped (since 1.5 s) and settled: the gravity wrench again.
  const massid::Wrench gravity =
      static_wrench(model, plant.joint_positions(), gravity_in_sensor(plant, options));
  const double rel = (plant.measured_wrench() - gravity).norm() / gravity.norm();
  std::cout << "[ plant    ] " << GetParam().name << " arm moving: largest dynamic force "
            << max_dyn << " N; stopped: relative difference " << rel << "; " << us
            << " us per 1 ms step (with the test's own work)\n";
  EXPECT_GT(max_dyn, 1.0);
  EXPECT_LT(rel, 1e-6);
  EXPECT_LT((plant.platform_pose().translation() - geometry.home.translation()).norm(), 1e-4);
}

TEST(PlantTiming, AdvanceOneMillisecond) {
  const massid::Model model =
      massid::load_urdf(std::string(MASSID_SOURCE_DIR) + "/examples/ur_like/ur_like.urdf");
  PlatformPlant plant(model, massid::emulator::default_geometry());
  massid::emulator::SpacecraftParameters sc;
  sc.mass = 60.0;
  sc.inertia = Eigen::Vector3d(6.0, 5.0, 4.0).asDiagonal();
  FreeFloatingReference ref(model, sc, Eigen::Isometry3d::Identity());
  const Eigen::VectorXd q = test_pose(model);
  plant.set_joints(q);
  ref.set_joints(q);
  const Eigen::VectorXd qd = Eigen::VectorXd::Constant(model.num_joints(), 0.1);
  const int n = 2000;
  auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) {
    plant.set_joint_command(q, qd);
    plant.advance(kDt);
  }
  const double plant_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) {
    ref.set_joint_command(q, qd);
    ref.advance(kDt);
  }
  const double ref_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  std::cout << "[ plant    ] ur_like: set_joint_command + advance(1 ms) = 1 RK4 step: plant "
            << plant_us << " us, free-floating reference " << ref_us << " us\n";
  RecordProperty("plant_advance_1ms_us", std::to_string(plant_us));
  RecordProperty("reference_advance_1ms_us", std::to_string(ref_us));
  EXPECT_NEAR(plant.time(), n * kDt, 1e-9);
  EXPECT_NEAR(ref.time(), n * kDt, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Examples, Plant,
                         ::testing::Values(Robot{"puma260", "examples/puma260/puma260.urdf"},
                                           Robot{"ur_like", "examples/ur_like/ur_like.urdf"},
                                           // 8 joints and a mimic finger
                                           Robot{"panda", "tests/data/robots/panda.urdf"}),
                         [](const ::testing::TestParamInfo<Robot>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace

namespace massid::emulator {
namespace {

SpacecraftParameters fifty_kg_spacecraft() {
  SpacecraftParameters sc;
  sc.mass = 50.0;
  sc.inertia = Eigen::Vector3d(5.0, 5.0, 5.0).asDiagonal();
  return sc;
}

// The PUMA's sensor frame has z down (the paper's): mounted upside down.
EmulationOptions puma_options(double duration) {
  EmulationOptions o;
  o.duration = duration;
  o.spacecraft = fifty_kg_spacecraft();
  o.platform_T_sensor.linear() =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return o;
}

double relative_position(const EmulationSummary& s) {
  return s.position_error_max_m / s.reference_excursion_m;
}
double relative_attitude(const EmulationSummary& s) {
  return s.attitude_error_max_deg / s.reference_excursion_deg;
}

IdentifiedModel predictor_of(const Model& model, const Eigen::VectorXd& standard) {
  BaseParameters base = find_base_parameters(model);
  Eigen::VectorXd values = base.K * standard;
  return IdentifiedModel::from_values(model, std::move(base), std::move(values));
}

// The admittance model against MuJoCo, open loop: fed the wrench that the
// free-floating reference's own interface sensor reads, the spacecraft model
// must move as the reference's spacecraft does. It checks the model's
// equations, frames and the sensor's sign at once, and shows why the joint
// commands carry their acceleration: held to first order, the servo's
// acceleration is a sawtooth at the command rate whose peaks the sensor
// samples, a bias that integrates into a drift of a third of the excursion.
TEST(Emulation, ReferenceSensorDrivesTheAdmittanceModelOntoTheReference) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const SpacecraftParameters sc = fifty_kg_spacecraft();
  const JointTrajectory maneuver = smooth_maneuver(model, 10.0);
  const auto run = [&](bool feed_acceleration) {
    FreeFloatingReference ref(model, sc, Eigen::Isometry3d::Identity());
    Eigen::VectorXd q, qd, qdd;
    maneuver(0.0, q, qd, qdd);
    ref.set_joints(q);
    SpacecraftState state = state_at_rest(sc, Eigen::Isometry3d::Identity());
    double error = 0.0, excursion = 0.0;
    for (int k = 0; k < 10000; ++k) {
      maneuver(k * kDt, q, qd, qdd);
      if (feed_acceleration) {
        ref.set_joint_command(q, qd, qdd);
      } else {
        ref.set_joint_command(q, qd);
      }
      step(sc, state, ref.interface_wrench(), kDt);
      ref.advance(kDt);
      const Eigen::Vector3d p = ref.interface_pose().translation();
      error = std::max(error, (interface_pose(sc, state).translation() - p).norm());
      excursion = std::max(excursion, p.norm());
    }
    std::cout << "[ emulate  ] open loop, joint acceleration "
              << (feed_acceleration ? "fed" : "not fed") << ": admittance model vs reference "
              << error << " m of " << excursion << " m\n";
    return error / excursion;
  };
  EXPECT_LT(run(true), 2e-3);
  EXPECT_GT(run(false), 0.05);
}

// With the robot's true gravity model the emulator's own error is what is
// left: one-tick delay, servo lag, integration. It must be far below the 5 %.
TEST(Emulation, WithTheTrueGravityModelTheErrorIsATenthOfAPercent) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const IdentifiedModel truth = predictor_of(model, nominal_standard_parameters(model));
  EmulationOptions o = puma_options(10.0);
  o.tare = false;
  const EmulationSummary s = run_emulation(model, truth, o, true);
  std::cout << "[ emulate  ] true model: " << 100 * relative_position(s) << " % and "
            << 100 * relative_attitude(s) << " % of " << s.reference_excursion_m << " m, "
            << s.reference_excursion_deg << " deg\n";
  EXPECT_EQ(s.supervisor_stops, 0);
  EXPECT_GT(s.reference_excursion_m, 5e-3);
  EXPECT_GT(s.reference_excursion_deg, 1.0);
  EXPECT_LT(relative_position(s), 1e-3);
  EXPECT_LT(relative_attitude(s), 1e-3);
}

// The targets, as the README's worked example runs them: the PUMA 260
// as built (a gripper and a cable harness its URDF lacks) measured on the
// paper's 30-pose plan for 1 s per pose at 1 kHz with sensor noise 0.05 N and
// 0.005 N m, identified with the nominal URDF, emulating a 50 kg spacecraft
// over a 10 s maneuver: within 5 % of the reference's excursion; the URDF's
// nominal inertials and no compensation fail by a wide margin.
TEST(Emulation, IdentifiedParametersMeetTheFivePercentTarget) {
  const std::string dir = MASSID_SOURCE_DIR "/examples/puma260/";
  const Model model = load_urdf(dir + "puma260.urdf");
  const Model as_built = load_urdf(dir + "puma260_as_built.urdf");
  ASSERT_GT(as_built.nominal_total_mass() - model.nominal_total_mass(), 0.4);

  Samples data = read_samples(model, read_csv(dir + "plan.csv"), WrenchColumns::Optional);
  SimulateOptions noise;
  noise.noise_force = 0.05;
  noise.noise_moment = 0.005;
  noise.repeat = 1000;
  noise.seed = 7;
  data.wrench = simulate_wrenches(as_built, data, noise);
  const auto repeat_rows = [&](const Eigen::MatrixXd& m) {
    Eigen::MatrixXd out(m.rows() * noise.repeat, m.cols());
    for (Eigen::Index r = 0; r < out.rows(); ++r) out.row(r) = m.row(r / noise.repeat);
    return out;
  };
  data.q = repeat_rows(data.q);
  data.gravity = repeat_rows(data.gravity);
  data.line.assign(static_cast<std::size_t>(data.q.rows()), 0);
  const BaseParameters base = find_base_parameters(model);
  const IdentifySummary id = identify(model, base, data);
  const IdentifiedModel identified = IdentifiedModel::from_values(model, base, id.value);
  const IdentifiedModel nominal = predictor_of(model, nominal_standard_parameters(model));

  const EmulationOptions o = puma_options(10.0);
  const EmulationSummary with = run_emulation(as_built, identified, o, true);
  const EmulationSummary urdf = run_emulation(as_built, nominal, o, true);
  const EmulationSummary none = run_emulation(as_built, identified, o, false);
  for (const auto& [name, s] : {std::pair{"identified", with}, {"nominal", urdf}, {"none", none}})
    std::cout << "[ emulate  ] " << name << ": " << 100 * relative_position(s) << " % and "
              << 100 * relative_attitude(s) << " % of the excursion, " << s.supervisor_stops
              << " stops, " << 10.0 / s.seconds << "x real time\n";
  EXPECT_EQ(with.supervisor_stops, 0);
  EXPECT_LT(relative_position(with), 0.05);
  EXPECT_LT(relative_attitude(with), 0.05);
  EXPECT_GE(urdf.supervisor_stops, 1);
  EXPECT_GT(relative_position(urdf), 20 * relative_position(with));
  EXPECT_GE(none.supervisor_stops, 1);
  EXPECT_GT(relative_position(none), 5.0);
}

}  // namespace
}  // namespace massid::emulator

// A ROS description's root link named "world" clashes with MuJoCo's world
// body: the MJCF body gets another name, the plant loads and reads the sensor
// at that body, and every other name is kept.
TEST(MjcfNames, RootLinkNamedWorldIsRenamedInternallyOnly) {
  using massid::emulator::mjcf_body_name;
  EXPECT_EQ(mjcf_body_name("world"), "massid_link_world");
  EXPECT_EQ(mjcf_body_name("massid_platform"), "massid_link_massid_platform");
  EXPECT_EQ(mjcf_body_name("base_link"), "base_link");
  EXPECT_EQ(mjcf_body_name("World"), "World");
  const std::string urdf =
      "<robot name=\"r\"><link name=\"world\"/>"
      "<joint name=\"fix\" type=\"fixed\"><parent link=\"world\"/><child link=\"base\"/></joint>"
      "<link name=\"base\"><inertial><mass value=\"2\"/><origin xyz=\"0 0 0.05\"/>"
      "<inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
      "</link>"
      "<joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/>"
      "<origin xyz=\"0 0 0.1\"/><axis xyz=\"0 1 0\"/>"
      "<limit lower=\"-2\" upper=\"2\" effort=\"1\" velocity=\"1\"/></joint>"
      "<link name=\"arm\"><inertial><mass value=\"1\"/><origin xyz=\"0.2 0 0\"/>"
      "<inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
      "</link></robot>";
  const massid::Model model = massid::load_urdf_string(urdf);
  ASSERT_EQ(model.sensor_link(), "world");
  const std::string mjcf =
      massid::emulator::robot_mjcf(model, {}, Eigen::Isometry3d::Identity(), 0);
  EXPECT_NE(mjcf.find("<body name=\"massid_link_world\""), std::string::npos) << mjcf;
  EXPECT_EQ(mjcf.find("<body name=\"world\""), std::string::npos) << mjcf;
  EXPECT_NE(mjcf.find("<body name=\"base\""), std::string::npos) << mjcf;
  EXPECT_NE(mjcf.find("<joint name=\"j1\""), std::string::npos) << mjcf;
  // The plant loads (it threw "repeated name in body array" before), and the
  // sensor reads the static weight: 3 kg, and the moment of the arm's 1 kg at
  // 0.2 m plus nothing of the base's centred mass.
  massid::emulator::PlatformPlant plant(model, massid::emulator::default_geometry());
  plant.set_joints(Eigen::VectorXd::Zero(1));
  const massid::Wrench w = plant.measured_wrench();
  EXPECT_NEAR(w[2], -3 * 9.80665, 1e-6);
  EXPECT_NEAR(w[4], 0.2 * 9.80665, 1e-6);  // (0.2, 0, z) x (0, 0, -9.81): my = 0.2 * 9.81
  EXPECT_NEAR(plant.sensor_pose().translation().z(),
              massid::emulator::default_geometry().home.translation().z(), 1e-12);
}

// ---------------------------------------------------------------------------
// Mimic joints. The gripper of mimic_support.hpp: finger_b follows finger_a
// (revolute) and slide_b follows slide_a (prismatic). The independent
// computation is massid on the same URDF without the <mimic> tags, five
// independent joints, the mimic positions (velocities, accelerations) set by
// the test from the coefficients (expand); massid's own model of the mimic
// joints must agree too.

namespace {

using massid::test::GripperMimics;

// Positive and negative multipliers and offsets, revolute and prismatic.
const GripperMimics kMimicCases[] = {{-1.5, 0.2, 0.5, 0.01}, {0.8, -0.3, -2.0, -0.02}};

struct MimicGripper {
  massid::Model with, without;
  explicit MimicGripper(const GripperMimics& c)
      : with(massid::load_urdf_string(massid::test::gripper_urdf(true, c), "", "g.urdf")),
        without(massid::load_urdf_string(massid::test::gripper_urdf(false), "", "g0.urdf")) {
    // Inertia tensors MuJoCo takes as they are (the URDF's violate the
    // triangle inequality, and the plant would put isotropic ones in their
    // place): principal moments 2, 3, 4 (x 1e-4 m^2 times the mass), turned.
    for (massid::Model* m : {&with, &without})
      for (massid::Link& link : m->links) {
        const Eigen::Matrix3d r =
            Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1.0, -0.4).normalized()).matrix();
        link.inertia =
            r * Eigen::Vector3d(2e-4, 3e-4, 4e-4).asDiagonal() * r.transpose() * link.mass;
      }
  }
  Eigen::VectorXd expand(const Eigen::VectorXd& q, bool derivative) const {
    return massid::test::expand(with, without, q, derivative);
  }
};

// The sensor turned on the platform so that gravity has components on all its axes.
PlantOptions turned_sensor() {
  PlantOptions options;
  options.platform_T_sensor.translation() = Eigen::Vector3d(0.02, -0.01, 0.05);
  options.platform_T_sensor.linear() =
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, -0.5, 0.3).normalized()).matrix();
  return options;
}

massid::Samples motion_samples(const Eigen::MatrixXd& q, const Eigen::MatrixXd& qd,
                               const Eigen::MatrixXd& qdd, const Eigen::MatrixXd& g) {
  massid::Samples s;
  s.q = q;
  s.qd = qd;
  s.qdd = qdd;
  s.gravity = g;
  s.line.assign(static_cast<std::size_t>(q.rows()), 1);
  return s;
}

TEST(MimicPlant, StaticWrenchEqualsMassidAtSeveralMasterPositions) {
  for (const GripperMimics& c : kMimicCases) {
    const MimicGripper g(c);
    ASSERT_EQ(g.with.num_joints(), 3);  // shoulder, finger_a, slide_a
    ASSERT_EQ(g.with.mimics.size(), 2u);
    const PlantOptions options = turned_sensor();
    PlatformPlant plant(g.with, massid::emulator::default_geometry(), options);
    // Master positions of both signs, the fingers beyond their limits too
    // (the plant does not limit joints).
    const double positions[][3] = {{0.0, 0.0, 0.0},
                                   {0.3, 0.4, 0.04},
                                   {-0.7, -0.5, -0.05},
                                   {1.2, 0.9, 0.08},
                                   {-1.5, 0.2, -0.1}};
    // Read as built (joints at 0: each mimic joint at its offset), right
    // after set_joints, and after 0.2 s held there by the servos.
    const auto check = [&](const Eigen::Vector3d& q, const char* when) {
      const Eigen::Vector3d gs = gravity_in_sensor(plant, options);
      const massid::Wrench measured = plant.measured_wrench();
      const massid::Wrench expected = static_wrench(g.without, g.expand(q, false), gs);
      const massid::Wrench own = static_wrench(g.with, q, gs);
      // A plant that ignored the coefficients (mimic at its master's position)
      // would be off by far more than the tolerance.
      Eigen::VectorXd naive = g.expand(q, false);
      naive[g.without.find_joint("finger_b")] = q[1];
      naive[g.without.find_joint("slide_b")] = q[2];
      const massid::Wrench wrong = static_wrench(g.without, naive, gs);
      const double rel = (measured - expected).norm() / expected.norm();
      std::cout << "[ mimic    ] static " << when << ", multipliers " << c.finger_multiplier << ", "
                << c.slide_multiplier << ", q " << q.transpose() << ": relative difference " << rel
                << " (coefficients ignored: " << (wrong - expected).norm() / expected.norm()
                << ")\n";
      EXPECT_LT(rel, 1e-9) << when << ", q " << q.transpose() << "\nmeasured "
                           << measured.transpose() << "\nexpected " << expected.transpose();
      EXPECT_LT((own - expected).norm(), 1e-12 * expected.norm());
      EXPECT_GT((wrong - expected).norm(), 1e-5 * expected.norm()) << q.transpose();
      EXPECT_LT((plant.joint_positions() - q).cwiseAbs().maxCoeff(), 1e-12) << when;
    };
    check(Eigen::Vector3d::Zero(), "as built");
    for (const auto& p : positions) {
      const Eigen::Vector3d q(p[0], p[1], p[2]);
      plant.set_joints(q);
      check(q, "placed");
      for (int k = 0; k < 200; ++k) plant.advance(kDt);
      check(q, "held");
    }
  }
}

// In motion: the joints follow a trajectory (computed torque), the mimic
// joints their masters. At every 1 ms tick the sensor reads what massid's
// dynamic model gives for the plant's joint positions and velocities and the
// joint accelerations the servo imposes (the command's, plus its correction
// of the tracking error: qdd + kp e + kd e'). massid is given a sensor at
// rest: the platform weighs 1e9 kg (inertia 1e8 kg m^2), so the arm's few N
// of reaction accelerate it by nm/s^2, which shows as 2e-8 N (it scales with
// 1 / mass: 2e-5 N at 1e6 kg). The mimic joints' tracking of their masters,
// which RK4 keeps at rounding, adds nothing measurable. Tolerance 1e-8 of
// the largest wrench, 4.6e-7 N; a mimic joint moved only to its master's
// positions (no velocity, no acceleration of its own) is off by 1 N.
TEST(MimicPlant, DynamicWrenchEqualsMassidAlongATrajectory) {
  for (const GripperMimics& c : kMimicCases) {
    const MimicGripper g(c);
    PlantOptions options = turned_sensor();
    options.platform_mass = 1e9;
    options.platform_inertia = Eigen::Matrix3d::Identity() * 1e8;
    PlatformPlant plant(g.with, massid::emulator::default_geometry(), options);
    // q_j(t) = q0_j + A_j sin^2(pi f_j t): from rest, the fingers fast.
    const Eigen::Vector3d q0(0.2, -0.1, 0.01), amplitude(0.8, 0.6, 0.05), freq(0.5, 1.5, 2.0);
    const auto trajectory = [&](double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                Eigen::VectorXd& qdd) {
      q.resize(3);
      qd.resize(3);
      qdd.resize(3);
      for (int j = 0; j < 3; ++j) {
        const double w = kPi * freq[j], s = std::sin(w * t);
        q[j] = q0[j] + amplitude[j] * s * s;
        qd[j] = amplitude[j] * w * std::sin(2.0 * w * t);
        qdd[j] = 2.0 * amplitude[j] * w * w * std::cos(2.0 * w * t);
      }
    };
    Eigen::VectorXd q, qd, qdd;
    trajectory(0.0, q, qd, qdd);
    plant.set_joints(q);
    const int n = 2000;
    Eigen::MatrixXd rq(n, 3), rqd(n, 3), racc(n, 3), rg(n, 3), measured(n, 6);
    Eigen::MatrixXd xq(n, 5), xqd(n, 5), xacc(n, 5), xacc_static(n, 5);
    double track = 0.0;
    for (int k = 0; k < n; ++k) {
      trajectory(k * kDt, q, qd, qdd);
      plant.set_joint_command(q, qd, qdd);
      const Eigen::VectorXd qp = plant.joint_positions(), vp = plant.joint_velocities();
      const Eigen::VectorXd acc = qdd + options.joint_kp * (q - qp) + options.joint_kd * (qd - vp);
      track = std::max(track, (q - qp).cwiseAbs().maxCoeff());
      rq.row(k) = qp.transpose();
      rqd.row(k) = vp.transpose();
      racc.row(k) = acc.transpose();
      rg.row(k) = gravity_in_sensor(plant, options).transpose();
      measured.row(k) = plant.measured_wrench().transpose();
      xq.row(k) = g.expand(qp, false).transpose();
      xqd.row(k) = g.expand(vp, true).transpose();
      xacc.row(k) = g.expand(acc, true).transpose();
      // A mimic joint that moved with its master's positions only (the
      // equality of positions, not of velocities and accelerations).
      Eigen::VectorXd a0 = g.expand(acc, true);
      a0[g.without.find_joint("finger_b")] = 0.0;
      a0[g.without.find_joint("slide_b")] = 0.0;
      xacc_static.row(k) = a0.transpose();
      plant.advance(kDt);
    }
    massid::SimulateOptions dynamic;
    dynamic.dynamic = true;
    const Eigen::MatrixXd expected =
        massid::simulate_wrenches(g.without, motion_samples(xq, xqd, xacc, rg), dynamic);
    const Eigen::MatrixXd own =
        massid::simulate_wrenches(g.with, motion_samples(rq, rqd, racc, rg), dynamic);
    Eigen::MatrixXd xqd_static = xqd;
    xqd_static.col(g.without.find_joint("finger_b")).setZero();
    xqd_static.col(g.without.find_joint("slide_b")).setZero();
    const Eigen::MatrixXd wrong = massid::simulate_wrenches(
        g.without, motion_samples(xq, xqd_static, xacc_static, rg), dynamic);
    massid::Samples at_rest;
    at_rest.q = xq;
    at_rest.gravity = rg;
    at_rest.line.assign(static_cast<std::size_t>(n), 1);
    const Eigen::MatrixXd gravity_only = massid::simulate_wrenches(g.without, at_rest);

    const double scale = expected.rowwise().norm().maxCoeff();
    const double err = (measured - expected).rowwise().norm().maxCoeff();
    const double own_err = (own - expected).rowwise().norm().maxCoeff();
    const double dyn = (expected - gravity_only).rowwise().norm().maxCoeff();
    const double mimic_dyn = (wrong - expected).rowwise().norm().maxCoeff();
    std::cout << "[ mimic    ] motion, multipliers " << c.finger_multiplier << ", "
              << c.slide_multiplier << ": max |w| " << scale << " N, dynamic part up to " << dyn
              << " N, the mimic joints' own motion " << mimic_dyn << " N; plant vs massid " << err
              << " (massid with mimic tags vs without " << own_err << "); joints within " << track
              << " of the command\n";
    EXPECT_GT(dyn, 2.0);
    EXPECT_GT(mimic_dyn, 0.2);
    EXPECT_LT(own_err, 1e-10 * scale);
    EXPECT_LT(err, 1e-8 * scale);
  }
}

// The MJCF gives each mimic joint a joint of its own and an equality
// constraint with MuJoCo's polynomial (q1 = c0 + c1 q2): offset, multiplier.
TEST(MimicPlant, MjcfHasTheMimicJointsAndTheirCoupling) {
  const MimicGripper g(kMimicCases[1]);
  const std::string bodies =
      massid::emulator::robot_mjcf(g.with, {}, Eigen::Isometry3d::Identity(), 0);
  for (const char* joint : {"shoulder", "finger_a", "finger_b", "slide_a", "slide_b"})
    EXPECT_NE(bodies.find("<joint name=\"" + std::string(joint) + "\""), std::string::npos)
        << joint << "\n"
        << bodies;
  EXPECT_NE(bodies.find("name=\"slide_b\" type=\"slide\""), std::string::npos) << bodies;
  const std::string eq = massid::emulator::mimic_equalities_mjcf(g.with, 2);
  EXPECT_NE(
      eq.find("<joint joint1=\"finger_b\" joint2=\"finger_a\" polycoef=\"-0.29999999999999999 "
              "0.80000000000000004 0 0 0\"/>"),
      std::string::npos)
      << eq;
  EXPECT_NE(eq.find("<joint joint1=\"slide_b\" joint2=\"slide_a\" polycoef=\"-0.02 -2 0 0 0\"/>"),
            std::string::npos)
      << eq;
  EXPECT_EQ(massid::emulator::mimic_equalities_mjcf(g.without, 2), "");
  EXPECT_EQ(massid::emulator::mjcf_joint_name("massid_platform_free"),
            "massid_joint_massid_platform_free");
  EXPECT_EQ(massid::emulator::mjcf_joint_name("finger_b"), "finger_b");
}

}  // namespace

namespace massid::emulator {
namespace {

std::string hint_placeholder(EmulatorSetting) { return "<HINT>"; }

// Why a run stopped names the settings that would help only through the
// caller's speller (the CLI's options): no option in the library's text.
TEST(DescribeStop, NamesTheSettingsThroughTheSpeller) {
  const EmulationOptions o;
  EmulationSummary s;
  EXPECT_EQ(describe_stop(s, o, hint_placeholder), "");
  s.supervisor_stops = 1;
  s.stop_detail = {3, 0.5, 0.4};
  for (const StopReason reason : {StopReason::Workspace, StopReason::TrackingError})
    for (const double excursion : {0.0, 100.0}) {
      s.stop_reason = reason;
      s.reference_excursion_deg = excursion;
      const std::string text = describe_stop(s, o, hint_placeholder);
      EXPECT_NE(text.find("to fix: "), std::string::npos) << text;
      EXPECT_NE(text.find("<HINT>"), std::string::npos) << text;
      EXPECT_EQ(text.find("--"), std::string::npos) << text;
    }
}

}  // namespace
}  // namespace massid::emulator

// The emulator's control step: gravity compensation in the tilted sensor
// frame, the admittance response to a dynamic wrench, and a supervisor that
// stops smoothly before the legs reach their limits.
#include <gtest/gtest.h>

#include "massid/core/base_parameters.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/emulator/controller.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid::emulator {
namespace {

// The PUMA 260 with its true base parameters, on the default platform, its
// sensor frame (z down, as in the paper) mounted upside down on the platform top.
struct PumaOnPlatform {
  Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  BaseParameters base = find_base_parameters(model);
  EmulatorModel em;
  PumaOnPlatform() {
    Eigen::VectorXd truth = base.K * nominal_standard_parameters(model);
    em.identified = IdentifiedModel::from_values(model, base, truth);
    em.spacecraft.mass = 50.0;
    em.spacecraft.inertia = Eigen::Vector3d(6.0, 7.0, 5.0).asDiagonal();
    em.spacecraft.body_T_interface.translation() << 0.0, 0.0, 0.4;
    em.geometry = default_geometry();
    em.platform_T_sensor.linear() =
        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  }
  // The static gravity wrench the robot exerts at q with the platform at `pose`.
  Wrench gravity_wrench(const Eigen::VectorXd& q, const Eigen::Isometry3d& pose) const {
    Samples s;
    s.q = q.transpose();
    s.gravity = ((pose * em.platform_T_sensor).linear().transpose() * em.gravity_world).transpose();
    return simulate_wrenches(model, s).row(0).transpose();
  }
};

TEST(Controller, StaticGravityIsCancelledAndThePlatformStaysHome) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.3, -1.2, 0.8);
  for (int k = 0; k < 1000; ++k) {
    control_step(s.em, data, s.gravity_wrench(q, data.command), q, data.command);
    EXPECT_LT(data.compensated.norm(), 1e-10);
  }
  EXPECT_EQ(data.state, SupervisorState::Running);
  EXPECT_LT((data.command.translation() - s.em.geometry.home.translation()).norm(), 1e-12);
}

// A sensor offset (or the gravity model's error at the starting pose) is
// removed by taring at rest, and only that: gravity still follows the pose.
TEST(Controller, TareRemovesAnOffsetAtRestAndGravityStillFollowsThePose) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  Wrench offset;
  offset << 0.8, -0.3, 1.5, 0.05, 0.02, -0.04;
  const Eigen::VectorXd q0 = Eigen::Vector3d(0.3, -1.2, 0.8);
  tare(s.em, data, s.gravity_wrench(q0, data.command) + offset, q0, data.command);
  EXPECT_LT((data.tare - offset).norm(), 1e-12);
  const Eigen::VectorXd q1 = Eigen::Vector3d(-1.0, -2.0, 2.5);
  for (const Eigen::VectorXd& q : {q0, q1}) {
    control_step(s.em, data, s.gravity_wrench(q, data.command) + offset, q, data.command);
    EXPECT_LT(data.compensated.norm(), 1e-10);
  }
  // Without the tare the offset pushes the spacecraft.
  EmulatorData untared(s.em);
  control_step(s.em, untared, s.gravity_wrench(q1, untared.command) + offset, q1, untared.command);
  EXPECT_LT((untared.compensated - offset).norm(), 1e-10);
  reset(s.em, data);
  EXPECT_EQ(data.tare, Wrench::Zero());
}

TEST(Controller, GravityIsRotatedIntoTheTiltedSensorFrame) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  Eigen::Isometry3d tilted = s.em.geometry.home;
  tilted.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()));
  const Eigen::VectorXd q = Eigen::Vector3d(-0.5, -2.0, 1.5);
  data.command = tilted;  // as if the platform had been commanded there
  control_step(s.em, data, s.gravity_wrench(q, tilted), q, tilted);
  EXPECT_LT(data.compensated.norm(), 1e-10);
  // Without compensation the raw wrench drives the admittance.
  s.em.compensate_gravity = false;
  EmulatorData raw(s.em);
  raw.command = tilted;
  control_step(s.em, raw, s.gravity_wrench(q, tilted), q, tilted);
  EXPECT_GT(raw.compensated.head<3>().norm(), 100.0);
}

TEST(Controller, ADynamicForceAcceleratesTheEmulatedSpacecraft) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.0, -1.5, 1.5);
  // A force along the sensor z axis through the spacecraft's centre of mass
  // (the interface sits 0.4 m along z from it): pure translation, a = F / M.
  Wrench push = Wrench::Zero();
  push[2] = 10.0;
  const double t = 0.5;
  for (int k = 0; k < 500; ++k)
    control_step(s.em, data, s.gravity_wrench(q, data.command) + push, q, data.command);
  const Eigen::Vector3d moved = data.command.translation() - s.em.geometry.home.translation();
  // Sensor z is platform -z (mounted upside down).
  const Eigen::Vector3d expected(0.0, 0.0, -0.5 * 10.0 / 50.0 * t * t);
  EXPECT_LT((moved - expected).norm(), 1e-9) << moved.transpose();
  EXPECT_LT(
      Eigen::AngleAxisd(data.command.linear() * s.em.geometry.home.linear().transpose()).angle(),
      1e-12);
}

TEST(Controller, SupervisorStopsSmoothlyBeforeALegLimit) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.0, -1.5, 1.5);
  Wrench push = Wrench::Zero();
  push[0] = 40.0;  // sideways: drives the platform into its leg limits
  Eigen::Isometry3d previous = data.command;
  double previous_step = 0.0, max_jump = 0.0;
  bool stopped_running = false;
  for (int k = 0; k < 6000; ++k) {
    control_step(s.em, data, s.gravity_wrench(q, data.command) + push, q, data.command);
    // Never past the stroke (nor the workspace).
    EXPECT_GE(leg_limit_margin(s.em.geometry, data.legs), 0.0) << "tick " << k;
    EXPECT_TRUE(within_workspace(s.em.geometry, data.command)) << "tick " << k;
    const double step = (data.command.translation() - previous.translation()).norm();
    max_jump = std::max(max_jump, std::abs(step - previous_step));
    previous_step = step;
    previous = data.command;
    stopped_running = stopped_running || data.state != SupervisorState::Running;
  }
  EXPECT_TRUE(stopped_running);
  EXPECT_EQ(data.state, SupervisorState::Stopped);
  EXPECT_NE(data.reason, StopReason::None);
  // No jump in pose or velocity: the per-tick motion changes by at most a
  // bounded acceleration times dt^2 (the push gives the interface about
  // 0.8 m/s^2 plus 1.1 m/s^2 from the turning it causes; braking adds 0.5),
  // while stopping dead would change it by the speed times dt (~1e-4 m here).
  EXPECT_LE(max_jump, 3.0 * s.em.dt * s.em.dt);
  EXPECT_GT(max_jump, 0.0);
}

TEST(Controller, TrackingErrorStopsThePlatform) {
  PumaOnPlatform s;
  EmulatorData data(s.em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.0, -1.5, 1.5);
  Eigen::Isometry3d off = data.command;
  off.translation().x() += 0.02;  // the platform is not where it was told to be
  control_step(s.em, data, s.gravity_wrench(q, off), q, off);
  EXPECT_NE(data.state, SupervisorState::Running);
  EXPECT_EQ(data.reason, StopReason::TrackingError);
}

}  // namespace
}  // namespace massid::emulator

namespace massid::emulator {
namespace {

// Admittance control with delay: the sensor also feels the robot's inertia
// (-m_r a) one loop delay late, so the emulated acceleration obeys
//   M a_k = F - m_r a_{k-n}   ->  stable only when m_r / M < 1.
// Shown here with a platform that follows the command n ticks late and a rigid
// (static) arm: the wrench it exerts on an accelerating, non-rotating platform
// is the static wrench with gravity replaced by g - a (linear in g).
struct DelayRun {
  double peak_force = 0.0;  // largest |compensated force|
  double final_accel = 0.0;
  SupervisorState state;
};

DelayRun run_with_delay(double spacecraft_mass, int delay_ticks) {
  PumaOnPlatform s;
  s.em.spacecraft.mass = spacecraft_mass;
  s.em.spacecraft.body_T_interface.setIdentity();  // pushes through the centre of mass
  s.em.supervisor.max_tracking_error = 0.05;
  EmulatorData data(s.em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.0, -1.5, 1.5);
  std::vector<Eigen::Isometry3d> commands(delay_ticks + 3, data.command);
  Wrench push = Wrench::Zero();
  push[1] = 2.0;  // an external push on the robot, sensor y
  const double dt = s.em.dt;
  DelayRun out;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  for (int k = 0; k < 1500; ++k) {
    // Platform: the command of n ticks ago; acceleration by second difference.
    const size_t n = commands.size();
    const Eigen::Isometry3d& platform = commands[n - 1 - delay_ticks];
    a = (commands[n - 1 - delay_ticks].translation() -
         2 * commands[n - 2 - delay_ticks].translation() +
         commands[n - 3 - delay_ticks].translation()) /
        (dt * dt);
    const Eigen::Vector3d g = s.em.gravity_world - a;  // apparent gravity, world
    Samples smp;
    smp.q = q.transpose();
    smp.gravity = ((platform * s.em.platform_T_sensor).linear().transpose() * g).transpose();
    const Wrench measured = simulate_wrenches(s.model, smp).row(0).transpose() + push;
    control_step(s.em, data, measured, q, platform);
    out.peak_force = std::max(out.peak_force, data.compensated.head<3>().norm());
    commands.erase(commands.begin());
    commands.push_back(data.command);
    if (data.state != SupervisorState::Running) break;
  }
  out.final_accel = a.norm();
  out.state = data.state;
  return out;
}

TEST(Controller, DelayedAdmittanceNeedsMoreEmulatedMassThanTheRobot) {
  const double robot = 10.6;  // kg on the sensor
  // Heavier spacecraft than robot: converges to a = F / (M + m_r).
  const DelayRun heavy = run_with_delay(1.25 * robot, 2);
  EXPECT_EQ(heavy.state, SupervisorState::Running);
  EXPECT_NEAR(heavy.final_accel, 2.0 / (2.25 * robot), 1e-3);
  EXPECT_LT(heavy.peak_force, 2.5);
  // Lighter: the force loop diverges until the supervisor stops it.
  const DelayRun light = run_with_delay(0.8 * robot, 2);
  EXPECT_NE(light.state, SupervisorState::Running);
  EXPECT_GT(light.peak_force, 20.0);
}

}  // namespace
}  // namespace massid::emulator

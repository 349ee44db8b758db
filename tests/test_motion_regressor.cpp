// The motion regressor (regressor.hpp: motion_regressor, with kinematics.hpp's
// forward_kinematics and upstream_kinematics) against Newton-Euler computed
// independently from positions alone.
//
// Compared:
//
//   massid:    motion_regressor(model, forward_kinematics(q, qd, qdd, g_s, sensor
//              motion)) * ParameterLayout::full().nominal(model).
//   reference: momentum_wrench (motion_support.hpp). The link poses come from an
//              Isometry3d chain over the URDF fields (origin, axis, type), the
//              sensor frame's pose from an analytic function of time (tilted,
//              at rest or moving: FrameTrajectory), the joints follow sums of
//              sines. Each link's linear momentum and its angular momentum
//              about the world origin are differentiated numerically in time;
//              the wrench on the sensor is weight minus the rate of change of
//              momentum, moved to the sensor origin and rotated into the sensor
//              frame. The sensor motion given to massid (omega, omega_dot,
//              accel) and the sensor-frame gravity R_s^T g_world are derived by
//              hand from the same analytic pose (and checked here against
//              differences of it).
//
//   Robots: every example (puma260, ur_like, branching, wrist_tool), with the
//   URDF's inertials and with random inertials (off-diagonal inertia terms,
//   mass on every link) so that all ten columns per link are exercised.
//
//   At rest: motion_regressor * pi_full = standard_regressor * pi_first_moments.
//
//   A sensor below movable joints: ur_like with the sensor at one of its links.
//   upstream_kinematics against the model loaded at the root (its
//   forward_kinematics, and differences of the chain's poses); the wrist
//   model's wrench against the momenta of the subtree moving in the root frame.
//
// Tolerances:
//   * finite differences: |massid - reference| <= 1e-6 |x| + 1e-9 (Euclidean
//     norms; N, N m for wrenches, rad/s, rad/s^2, m/s^2 for motion).
//     Five-point stencils with h = 1e-3 s: truncation ~h^4 f^(6)/90 ~ 1e-11
//     at these frequencies (<= 3 rad/s per sine), round-off ~64 eps |c| /
//     (12 h^2) ~ 1e-9 m/s^2 on the accelerations. Observed: wrenches <= 2e-10
//     relative, link motion (a nested difference for omega_dot) <= 1.2e-9,
//     so 1e-6 is a wide margin, while a wrong term of the recursion (a missing
//     Coriolis or centripetal term, a sign, a swapped inertia column; each
//     tried by mutating a copy of the code) is O(1e-2..1) relative and fails.
//   * algebraic identities (rest vs static regressor, upstream vs the root
//     model's recursion): 1e-12 relative to the magnitude, round-off only.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"
#include "massid/core/simulate.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "motion_support.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::FrameTrajectory;
using test::SineTrajectory;
using test::Snapshot;
using test::Wrench6;

constexpr double kStep = 1e-3;                         // s, finite-difference step
constexpr double kRelative = 1e-6;                     // finite differences, relative to |w|
constexpr double kAbsolute = 1e-9;                     // N, N m floor
constexpr double kRoundOff = 1e-12;                    // algebraic identities, relative
constexpr int kInstants = 25;                          // sample times per trajectory
const Eigen::Vector3d kGravityWorld(0.8, -0.5, -9.7);  // tilted on purpose

// Largest errors over a run, for the log.
struct Worst {
  double rel = 0.0, abs = 0.0, scale = 0.0;
  void add(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
    const double e = (got - want).norm();
    abs = std::max(abs, e);
    rel = std::max(rel, e / std::max(want.norm(), 1e-300));
    scale = std::max(scale, want.norm());
  }
  void print(const std::string& what) const {
    std::cout << "[ motion   ] " << what << ": max |reference| " << scale << ", max |error| " << abs
              << ", max relative " << rel << "\n";
  }
};

bool close(const Eigen::VectorXd& got, const Eigen::VectorXd& want, double rel, double abs) {
  return (got - want).norm() <= rel * want.norm() + abs;
}

// massid's wrench for the nominal parameters of `model`.
struct Massid {
  explicit Massid(const Model& m)
      : model(m),
        kin(m),
        Y(6, ParameterLayout::full().size(m)),
        pi(ParameterLayout::full().nominal(m)) {}
  Wrench6 operator()(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     const Eigen::VectorXd& qdd, const Eigen::Vector3d& g,
                     const FrameMotion& sensor) {
    forward_kinematics(model, kin, q, qd, qdd, g, sensor);
    motion_regressor(model, kin, Y);
    return Y * pi;
  }
  const Model& model;
  KinematicsData kin;
  Eigen::MatrixXd Y;
  Eigen::VectorXd pi;
};

// The reference wrench of the whole model at time t.
Wrench6 reference_wrench(const Model& model, const SineTrajectory& joints,
                         const FrameTrajectory& frame, double t) {
  const test::SnapshotFn at = [&](double tau) {
    Snapshot s;
    s.sensor = frame.pose(tau);
    for (const Eigen::Isometry3d& T : test::link_poses(model, joints.q(tau)))
      s.bodies.push_back(s.sensor * T);
    return s;
  };
  return test::momentum_wrench(test::bodies_of(model), at, kGravityWorld, t, kStep);
}

class MotionRegressorTest : public ::testing::TestWithParam<test::Example> {
 protected:
  // massid against the momentum differences along one trajectory.
  void compare_along_trajectory(const Model& model, bool moving, std::uint64_t seed,
                                const std::string& variant) {
    std::mt19937_64 rng(seed);
    const SineTrajectory joints = test::joint_trajectory(model.joints, rng);
    const FrameTrajectory frame = FrameTrajectory::random(rng, moving);
    Massid massid_w(model);
    Worst worst;
    for (int i = 0; i < kInstants; ++i) {
      const double t = 0.137 * i;
      const Eigen::Matrix3d Rs = frame.pose(t).linear();
      const Wrench6 got = massid_w(joints.q(t), joints.qd(t), joints.qdd(t),
                                   Rs.transpose() * kGravityWorld, frame.motion(t));
      const Wrench6 want = reference_wrench(model, joints, frame, t);
      worst.add(got, want);
      EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
          << variant << " t = " << t << "\nmassid    " << got.transpose() << "\nreference "
          << want.transpose();
    }
    worst.print(std::string(GetParam().name) + " (" + variant + ")");
  }
};

// The harness itself: the hand-derived sensor motion is the motion of the pose.
TEST_P(MotionRegressorTest, AnalyticSensorMotionMatchesPoseDifferences) {
  std::mt19937_64 rng(11);
  const FrameTrajectory frame = FrameTrajectory::random(rng, true);
  const auto pose = [&](double tau) { return frame.pose(tau); };
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.21 * i;
    const FrameMotion a = frame.motion(t), d = test::frame_motion_by_differences(pose, t, kStep);
    EXPECT_TRUE(close(a.omega, d.omega, kRelative, kAbsolute)) << t;
    EXPECT_TRUE(close(a.omega_dot, d.omega_dot, kRelative, kAbsolute)) << t;
    EXPECT_TRUE(close(a.accel, d.accel, kRelative, kAbsolute)) << t;
  }
}

// Link poses and link-frame motion of forward_kinematics against the chain's
// poses and their differences (gravity zero: accel is the origin acceleration).
TEST_P(MotionRegressorTest, ForwardKinematicsMatchesPoseDifferences) {
  const Model model = load_urdf(GetParam().urdf);
  std::mt19937_64 rng(5);
  const SineTrajectory joints = test::joint_trajectory(model.joints, rng);
  const FrameTrajectory frame = FrameTrajectory::random(rng, true);
  KinematicsData kin(model);
  Worst worst;
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.173 * i;
    forward_kinematics(model, kin, joints.q(t), joints.qd(t), joints.qdd(t),
                       Eigen::Vector3d::Zero(), frame.motion(t));
    const std::vector<Eigen::Isometry3d> T = test::link_poses(model, joints.q(t));
    for (int l = 0; l < model.num_links(); ++l) {
      const std::size_t ul = static_cast<std::size_t>(l);
      EXPECT_LT((kin.rotation[ul] - T[ul].linear()).norm(), kRoundOff);
      EXPECT_LT((kin.position[ul] - T[ul].translation()).norm(), kRoundOff);
      const auto pose = [&](double tau) {
        return frame.pose(tau) * test::link_poses(model, joints.q(tau))[ul];
      };
      const FrameMotion d = test::frame_motion_by_differences(pose, t, kStep);
      Eigen::VectorXd got(9), want(9);
      got << kin.omega[ul], kin.omega_dot[ul], kin.accel[ul];
      want << d.omega, d.omega_dot, d.accel;
      worst.add(got, want);
      EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
          << "link " << model.links[ul].name << " t = " << t << "\nmassid    " << got.transpose()
          << "\nreference " << want.transpose();
    }
  }
  worst.print(std::string(GetParam().name) + " (link motion)");
}

TEST_P(MotionRegressorTest, MatchesMomentumDifferencesSensorAtRest) {
  const Model model = load_urdf(GetParam().urdf);
  compare_along_trajectory(model, false, 21, "sensor at rest");
}

TEST_P(MotionRegressorTest, MatchesMomentumDifferencesMovingSensor) {
  const Model model = load_urdf(GetParam().urdf);
  compare_along_trajectory(model, true, 22, "moving sensor");
}

TEST_P(MotionRegressorTest, MatchesMomentumDifferencesRandomInertials) {
  std::mt19937_64 rng(23);
  const Model model = test::with_random_inertials(load_urdf(GetParam().urdf), rng);
  compare_along_trajectory(model, true, 24, "random inertials, moving sensor");
}

// simulate_wrenches(dynamic) reads velocities, accelerations and the sensor
// motion (wx..wz, dwx..dwz, ax..az) from Samples: the same reference.
TEST_P(MotionRegressorTest, SimulateDynamicMatchesMomentumDifferences) {
  const Model model = load_urdf(GetParam().urdf);
  std::mt19937_64 rng(31);
  const SineTrajectory joints = test::joint_trajectory(model.joints, rng);
  const FrameTrajectory frame = FrameTrajectory::random(rng, true);
  Samples s;
  s.q.resize(kInstants, model.num_joints());
  s.qd.resize(kInstants, model.num_joints());
  s.qdd.resize(kInstants, model.num_joints());
  s.gravity.resize(kInstants, 3);
  s.sensor_motion.resize(kInstants, 9);
  s.line.assign(kInstants, 0);
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.119 * i;
    if (model.num_joints() > 0) {  // (a row of a 0-column matrix: a null pointer plus an offset)
      s.q.row(i) = joints.q(t).transpose();
      s.qd.row(i) = joints.qd(t).transpose();
      s.qdd.row(i) = joints.qdd(t).transpose();
    }
    s.gravity.row(i) = (frame.pose(t).linear().transpose() * kGravityWorld).transpose();
    const FrameMotion m = frame.motion(t);
    s.sensor_motion.row(i) << m.omega.transpose(), m.omega_dot.transpose(), m.accel.transpose();
  }
  SimulateOptions options;
  options.dynamic = true;
  const Eigen::MatrixXd W = simulate_wrenches(model, s, options);
  ASSERT_EQ(W.rows(), kInstants);
  Worst worst;
  for (int i = 0; i < kInstants; ++i) {
    const Wrench6 got = W.row(i).transpose();
    const Wrench6 want = reference_wrench(model, joints, frame, 0.119 * i);
    worst.add(got, want);
    EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
        << "row " << i << "\nmassid    " << got.transpose() << "\nreference " << want.transpose();
  }
  worst.print(std::string(GetParam().name) + " (simulate_wrenches dynamic)");
}

// At rest the motion regressor is the static one: same wrench, the mass and
// first-moment columns equal, the inertia columns zero.
TEST_P(MotionRegressorTest, AtRestEqualsStaticRegressor) {
  const Model model = load_urdf(GetParam().urdf);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  const Eigen::VectorXd pi_full = ParameterLayout::full().nominal(model);
  const Eigen::VectorXd pi_static = ParameterLayout::first_moments().nominal(model);
  ASSERT_EQ(pi_static, nominal_standard_parameters(model));
  KinematicsData kin(model), kin_static(model);
  Eigen::MatrixXd Y(6, pi_full.size()), S(6, num_standard_parameters(model));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_joints());
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < model.num_joints(); ++j) q[j] = model.joints[j].generic_position(u(rng));
    const Eigen::Vector3d g = 9.81 * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    forward_kinematics(model, kin, q, zero, zero, g, FrameMotion{});
    motion_regressor(model, kin, Y);
    forward_kinematics(model, kin_static, q);
    standard_regressor(model, kin_static, g, S);
    const Wrench6 w = Y * pi_full, ws = S * pi_static;
    EXPECT_LT((w - ws).norm(), kRoundOff * (1.0 + ws.norm())) << "trial " << trial;
    for (int l = 0; l < model.num_links(); ++l) {
      const double scale = 1.0 + S.middleCols(kParamsPerLink * l, kParamsPerLink).norm();
      EXPECT_LT((Y.middleCols(10 * l, 4) - S.middleCols(kParamsPerLink * l, kParamsPerLink)).norm(),
                kRoundOff * scale)
          << model.links[static_cast<std::size_t>(l)].name;
      EXPECT_EQ(Y.middleCols(10 * l + 4, 6).cwiseAbs().maxCoeff(), 0.0)
          << model.links[static_cast<std::size_t>(l)].name;
    }
  }
  // simulate_wrenches: dynamic without velocity columns is the static wrench.
  const Samples plan = test::load_plan(model, GetParam().plan);
  SimulateOptions dynamic;
  dynamic.dynamic = true;
  const Eigen::MatrixXd Wd = simulate_wrenches(model, plan, dynamic);
  const Eigen::MatrixXd Ws = simulate_wrenches(model, plan);
  ASSERT_EQ(Wd.rows(), Ws.rows());
  for (int i = 0; i < Ws.rows(); ++i)
    EXPECT_LT((Wd.row(i) - Ws.row(i)).norm(), kRoundOff * (1.0 + Ws.row(i).norm())) << i;
}

INSTANTIATE_TEST_SUITE_P(Examples, MotionRegressorTest, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

// ---------------------------------------------------------------------------
// A sensor below movable joints: ur_like loaded with the sensor at one of its
// links (the upstream chain then holds the joints above it), against the same
// URDF loaded at its root.

class WristSensorTest : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    const std::string path = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";
    root_ = load_urdf(path);
    wrist_ = load_urdf(path, GetParam());
    ASSERT_EQ(wrist_.sensor_link(), GetParam());
    ASSERT_EQ(wrist_.root_link, root_.sensor_link());
    ASSERT_FALSE(wrist_.upstream.empty());
    sensor_in_root_ = root_.find_link(GetParam());
    ASSERT_GE(sensor_in_root_, 0);
    for (const Link& l : wrist_.links) {
      const int r = root_.find_link(l.name);
      ASSERT_GE(r, 0) << l.name;
      const Link& lr = root_.links[static_cast<std::size_t>(r)];
      ASSERT_EQ(l.mass, lr.mass) << l.name;
      ASSERT_EQ(l.com, lr.com) << l.name;
      ASSERT_EQ(l.inertia, lr.inertia) << l.name;
      link_in_root_.push_back(r);
    }
    // The measured subtree is the root model's subtree below the sensor link.
    int subtree = 0;
    for (int l = 0; l < root_.num_links(); ++l) {
      for (int a = l; a >= 0; a = root_.links[static_cast<std::size_t>(a)].parent) {
        if (a == sensor_in_root_) {
          ++subtree;
          break;
        }
      }
    }
    ASSERT_EQ(subtree, wrist_.num_links());
    for (const Joint& j : wrist_.joints) joint_in_root_.push_back(root_.find_joint(j.name));
    for (const Joint& j : wrist_.upstream_joints)
      upstream_in_root_.push_back(root_.find_joint(j.name));
    ASSERT_EQ(wrist_.num_joints() + wrist_.num_upstream_joints(), root_.num_joints());
    for (int j : joint_in_root_) ASSERT_GE(j, 0);
    for (int j : upstream_in_root_) ASSERT_GE(j, 0);
    std::mt19937_64 rng(51);
    joints_ = test::joint_trajectory(root_.joints, rng);
  }

  static Eigen::VectorXd pick(const Eigen::VectorXd& x, const std::vector<int>& index) {
    Eigen::VectorXd y(static_cast<Eigen::Index>(index.size()));
    for (std::size_t k = 0; k < index.size(); ++k) y[static_cast<Eigen::Index>(k)] = x[index[k]];
    return y;
  }

  // The subtree's wrench on the sensor link from its momenta in the root frame.
  Wrench6 reference(const Eigen::Vector3d& g_root, double t) const {
    const test::SnapshotFn at = [&](double tau) {
      const std::vector<Eigen::Isometry3d> T = test::link_poses(root_, joints_.q(tau));
      Snapshot s;
      s.sensor = T[static_cast<std::size_t>(sensor_in_root_)];
      for (int r : link_in_root_) s.bodies.push_back(T[static_cast<std::size_t>(r)]);
      return s;
    };
    return test::momentum_wrench(test::bodies_of(wrist_), at, g_root, t, kStep);
  }

  Model root_, wrist_;
  int sensor_in_root_ = -1;
  std::vector<int> link_in_root_, joint_in_root_, upstream_in_root_;
  SineTrajectory joints_;
};

TEST_P(WristSensorTest, UpstreamKinematicsMatchesRootModel) {
  KinematicsData kin(root_);
  const std::size_t s = static_cast<std::size_t>(sensor_in_root_);
  Worst worst;
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.191 * i;
    const Eigen::VectorXd q = joints_.q(t), qd = joints_.qd(t), qdd = joints_.qdd(t);
    const SensorPose up =
        upstream_kinematics(wrist_, pick(q, upstream_in_root_), pick(qd, upstream_in_root_),
                            pick(qdd, upstream_in_root_));
    // Orientation: the root model's recursion and the independent chain.
    forward_kinematics(root_, kin, q, qd, qdd, Eigen::Vector3d::Zero(), FrameMotion{});
    EXPECT_LT((up.rotation - kin.rotation[s]).norm(), kRoundOff) << t;
    EXPECT_LT((up.rotation - test::link_poses(root_, q)[s].linear()).norm(), kRoundOff) << t;
    // At rest: the same orientation, no motion.
    const Eigen::VectorXd none(0);
    const SensorPose still = upstream_kinematics(wrist_, pick(q, upstream_in_root_), none, none);
    EXPECT_LT((still.rotation - up.rotation).norm(), kRoundOff) << t;
    EXPECT_EQ(still.motion.omega, Eigen::Vector3d::Zero());
    EXPECT_EQ(still.motion.omega_dot, Eigen::Vector3d::Zero());
    EXPECT_EQ(still.motion.accel, Eigen::Vector3d::Zero());
    // Motion in the sensor frame: the root model's link motion (gravity zero,
    // so accel is the origin's acceleration), and differences of the chain.
    EXPECT_TRUE(close(up.motion.omega, kin.omega[s], kRoundOff, kRoundOff)) << t;
    EXPECT_TRUE(close(up.motion.omega_dot, kin.omega_dot[s], kRoundOff, kRoundOff)) << t;
    EXPECT_TRUE(close(up.motion.accel, kin.accel[s], kRoundOff, kRoundOff)) << t;
    const auto pose = [&](double tau) { return test::link_poses(root_, joints_.q(tau))[s]; };
    const FrameMotion d = test::frame_motion_by_differences(pose, t, kStep);
    Eigen::VectorXd got(9), want(9);
    got << up.motion.omega, up.motion.omega_dot, up.motion.accel;
    want << d.omega, d.omega_dot, d.accel;
    worst.add(got, want);
    EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
        << t << "\nmassid    " << got.transpose() << "\nreference " << want.transpose();
  }
  worst.print(std::string("ur_like at ") + GetParam() + " (upstream motion)");
}

TEST_P(WristSensorTest, WrenchMatchesSubtreeMomentum) {
  const Eigen::Vector3d g_root = kGravityWorld;
  Massid massid_w(wrist_);
  KinematicsData kin(root_);
  Worst worst, worst_root;
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.191 * i;
    const Eigen::VectorXd q = joints_.q(t), qd = joints_.qd(t), qdd = joints_.qdd(t);
    const SensorPose up =
        upstream_kinematics(wrist_, pick(q, upstream_in_root_), pick(qd, upstream_in_root_),
                            pick(qdd, upstream_in_root_));
    const Wrench6 got =
        massid_w(pick(q, joint_in_root_), pick(qd, joint_in_root_), pick(qdd, joint_in_root_),
                 up.rotation.transpose() * g_root, up.motion);
    const Wrench6 want = reference(g_root, t);
    worst.add(got, want);
    EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
        << t << "\nmassid    " << got.transpose() << "\nreference " << want.transpose();

    // The root model's own link wrenches (body_regressor, root frame) summed
    // over the subtree and moved to the sensor link: the same to round-off.
    forward_kinematics(root_, kin, q, qd, qdd, g_root, FrameMotion{});
    const Eigen::VectorXd pi = ParameterLayout::full().nominal(root_);
    Eigen::Vector3d F = Eigen::Vector3d::Zero(), M = Eigen::Vector3d::Zero();
    const std::size_t s = static_cast<std::size_t>(sensor_in_root_);
    for (int r : link_in_root_) {
      const std::size_t ur = static_cast<std::size_t>(r);
      const Wrench6 b =
          body_regressor(kin.omega[ur], kin.omega_dot[ur], kin.accel[ur]) * pi.segment<10>(10 * r);
      const Eigen::Vector3d f = kin.rotation[ur] * b.head<3>();
      F -= f;
      M -= kin.rotation[ur] * b.tail<3>() + (kin.position[ur] - kin.position[s]).cross(f);
    }
    Wrench6 from_root;
    from_root << kin.rotation[s].transpose() * F, kin.rotation[s].transpose() * M;
    worst_root.add(got, from_root);
    EXPECT_TRUE(close(got, from_root, kRoundOff * 10, kRoundOff)) << t;
  }
  worst.print(std::string("ur_like at ") + GetParam() + " (wrench vs subtree momenta)");
  worst_root.print(std::string("ur_like at ") + GetParam() + " (wrench vs root model's links)");
}

// The file path: samples with the upstream joints' positions, velocities and
// accelerations and no gx,gy,gz (gravity and sensor motion from the upstream
// joints, root gravity -9.80665 z), then simulate_wrenches(dynamic). With no
// movable joint above the sensor (base_link), gx,gy,gz columns instead.
TEST_P(WristSensorTest, SimulateFromUpstreamColumnsMatchesSubtreeMomentum) {
  std::vector<std::string> names;
  std::vector<Eigen::VectorXd> columns;
  const auto add = [&](const std::vector<Joint>& joints, const std::vector<int>& index) {
    for (std::size_t k = 0; k < joints.size(); ++k) {
      for (const char* suffix : {"", "_vel", "_acc"}) {
        names.push_back(joints[k].name + suffix);
        Eigen::VectorXd c(kInstants);
        for (int i = 0; i < kInstants; ++i) {
          const double t = 0.191 * i;
          const Eigen::VectorXd x = std::string(suffix).empty()     ? joints_.q(t)
                                    : std::string(suffix) == "_vel" ? joints_.qd(t)
                                                                    : joints_.qdd(t);
          c[i] = x[index[k]];
        }
        columns.push_back(c);
      }
    }
  };
  add(wrist_.joints, joint_in_root_);
  add(wrist_.upstream_joints, upstream_in_root_);
  const Eigen::Vector3d g_root(0.0, 0.0, -kStandardGravity);
  if (wrist_.num_upstream_joints() == 0) {
    // Only fixed joints above: the file gives gravity in the sensor frame.
    const Eigen::VectorXd none(0);
    const Eigen::Vector3d g =
        upstream_kinematics(wrist_, none, none, none).rotation.transpose() * g_root;
    for (int k = 0; k < 3; ++k) {
      names.push_back(std::string("g") + "xyz"[k]);
      columns.push_back(Eigen::VectorXd::Constant(kInstants, g[k]));
    }
  }
  const Samples s = samples_from_columns(wrist_, names, columns, WrenchColumns::Optional);
  ASSERT_EQ(s.gravity_from_upstream, wrist_.num_upstream_joints() > 0);
  ASSERT_EQ(s.has_sensor_motion(), wrist_.num_upstream_joints() > 0);
  SimulateOptions options;
  options.dynamic = true;
  const Eigen::MatrixXd W = simulate_wrenches(wrist_, s, options);
  ASSERT_EQ(W.rows(), kInstants);
  Worst worst;
  for (int i = 0; i < kInstants; ++i) {
    const Wrench6 got = W.row(i).transpose();
    const Wrench6 want = reference(g_root, 0.191 * i);
    worst.add(got, want);
    EXPECT_TRUE(close(got, want, kRelative, kAbsolute))
        << "row " << i << "\nmassid    " << got.transpose() << "\nreference " << want.transpose();
  }
  worst.print(std::string("ur_like at ") + GetParam() + " (samples from upstream columns)");
}

INSTANTIATE_TEST_SUITE_P(UrLike, WristSensorTest,
                         ::testing::Values("base_link", "upper_arm_link", "wrist_2_link", "tool"),
                         [](const auto& info) { return std::string(info.param); });

}  // namespace
}  // namespace massid

// Joint trajectories of the emulator: the clamped cubic spline through the
// samples of a trajectory file, and the built-in smooth maneuver.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/emulator/joint_trajectory.hpp"
#include "massid/io/urdf.hpp"

namespace massid::emulator {
namespace {

struct State {
  Eigen::VectorXd q, qd, qdd;
};

State at(const JointTrajectory& f, double t) {
  State s;
  f(t, s.q, s.qd, s.qdd);
  return s;
}

double max_abs(const Eigen::VectorXd& v) { return v.cwiseAbs().maxCoeff(); }

// Times strictly inside the segments, at least `margin` away from every knot.
std::vector<double> inner_times(const Eigen::VectorXd& t, int per_segment, double margin) {
  std::vector<double> out;
  for (Eigen::Index k = 0; k + 1 < t.size(); ++k)
    for (int i = 0; i < per_segment; ++i) {
      const double u = (i + 0.5) / per_segment;
      const double time = t[k] + u * (t[k + 1] - t[k]);
      if (time - t[k] > margin && t[k + 1] - time > margin) out.push_back(time);
    }
  return out;
}

// Derivatives against central differences: of q for qd (h = 1e-6), of qd for
// qdd (h = 1e-5). Tolerances relative to the size of the derivative.
void expect_consistent_derivatives(const JointTrajectory& f, const std::vector<double>& times) {
  for (double t : times) {
    const State s = at(f, t);
    const double h1 = 1e-6, h2 = 1e-5;
    const Eigen::VectorXd qd_fd = (at(f, t + h1).q - at(f, t - h1).q) / (2 * h1);
    const Eigen::VectorXd qdd_fd = (at(f, t + h2).qd - at(f, t - h2).qd) / (2 * h2);
    for (Eigen::Index j = 0; j < s.q.size(); ++j) {
      EXPECT_NEAR(s.qd[j], qd_fd[j], 1e-7 * (1 + std::abs(s.qd[j]))) << "t " << t << " joint " << j;
      EXPECT_NEAR(s.qdd[j], qdd_fd[j], 1e-6 * (1 + std::abs(s.qdd[j])))
          << "t " << t << " joint " << j;
    }
  }
}

// Non-uniform knots, three joints with unrelated motions.
struct Knots {
  Eigen::VectorXd t;
  Eigen::MatrixXd q;
  Knots() : t(6), q(6, 3) {
    t << 0.2, 0.5, 1.3, 1.45, 2.6, 3.0;
    q << 0.0, -1.5, 1.5,   //
        0.3, -1.4, 1.6,    //
        -0.2, -0.9, 2.1,   //
        -0.25, -1.0, 2.0,  //
        0.8, -2.0, 0.7,    //
        0.1, -1.5, 1.5;
  }
};

// ---------------------------------------------------------------- spline_trajectory

TEST(SplineTrajectory, PassesThroughEveryKnot) {
  const Knots k;
  const JointTrajectory f = spline_trajectory(k.t, k.q);
  for (Eigen::Index r = 0; r < k.t.size(); ++r) {
    const State s = at(f, k.t[r]);
    ASSERT_EQ(s.q.size(), 3);
    EXPECT_LT(max_abs(s.q - k.q.row(r).transpose()), 1e-12) << "knot " << r;
  }
}

TEST(SplineTrajectory, AtRestAtTheEndsAndHeldOutside) {
  const Knots k;
  const JointTrajectory f = spline_trajectory(k.t, k.q);
  const double t0 = k.t[0], tn = k.t[k.t.size() - 1];
  // Clamped: the velocity tends to zero at the first and last knot...
  EXPECT_LT(max_abs(at(f, t0 + 1e-9).qd), 1e-6);
  EXPECT_LT(max_abs(at(f, tn - 1e-9).qd), 1e-6);
  EXPECT_LT(max_abs(at(f, t0).qd), 1e-15);
  EXPECT_LT(max_abs(at(f, tn).qd), 1e-15);
  // ...but not in between (so the check above is not trivially met).
  EXPECT_GT(max_abs(at(f, t0 + 0.05).qd), 1e-2);
  EXPECT_GT(max_abs(at(f, tn - 0.05).qd), 1e-2);
  // Held at the first row before t0 and the last after tn.
  for (double t : {t0 - 10.0, t0 - 1e-3, tn + 1e-3, tn + 10.0}) {
    const State s = at(f, t);
    const Eigen::VectorXd held = k.q.row(t < t0 ? 0 : k.t.size() - 1).transpose();
    EXPECT_EQ(s.q, held) << "t " << t;
    EXPECT_EQ(s.qd, Eigen::VectorXd::Zero(3)) << "t " << t;
    EXPECT_EQ(s.qdd, Eigen::VectorXd::Zero(3)) << "t " << t;
  }
}

TEST(SplineTrajectory, DerivativesMatchFiniteDifferences) {
  const Knots k;
  const JointTrajectory f = spline_trajectory(k.t, k.q);
  const std::vector<double> times = inner_times(k.t, 7, 1e-4);
  ASSERT_GE(times.size(), 30u);
  expect_consistent_derivatives(f, times);
}

TEST(SplineTrajectory, PositionVelocityAndAccelerationAreContinuousAtInteriorKnots) {
  const Knots k;
  const JointTrajectory f = spline_trajectory(k.t, k.q);
  for (Eigen::Index r = 1; r + 1 < k.t.size(); ++r) {
    const State lo = at(f, k.t[r] - 1e-9), hi = at(f, k.t[r] + 1e-9);
    EXPECT_LT(max_abs(hi.q - lo.q), 1e-7) << "knot " << r;
    EXPECT_LT(max_abs(hi.qd - lo.qd), 1e-6) << "knot " << r;
    EXPECT_LT(max_abs(hi.qdd - lo.qdd), 1e-6) << "knot " << r;
    // The knot is passed while moving: continuity is not met by standing still.
    EXPECT_GT(max_abs(lo.qd), 1e-2) << "knot " << r;
  }
}

TEST(SplineTrajectory, ReproducesACubicWithZeroEndSlopes) {
  // s(u) = 3u^2 - 2u^3 has s'(0) = s'(1) = 0: the clamped spline through any
  // samples of it is s itself. Second joint: the same shape, shifted, scaled
  // and reversed, on a time axis [2, 5] via u = (t - 2) / 3.
  const auto s = [](double u) { return 3 * u * u - 2 * u * u * u; };
  const auto ds = [](double u) { return 6 * u - 6 * u * u; };
  const auto dds = [](double u) { return 6 - 12 * u; };
  const std::vector<double> us{0.0, 0.15, 0.4, 0.55, 0.8, 1.0};
  Eigen::VectorXd t(6);
  Eigen::MatrixXd q(6, 2);
  for (int r = 0; r < 6; ++r) {
    t[r] = 2 + 3 * us[r];
    q(r, 0) = s(us[r]);
    q(r, 1) = 1.0 - 0.5 * s(us[r]);
  }
  const JointTrajectory f = spline_trajectory(t, q);
  for (int i = 0; i <= 300; ++i) {
    const double u = i / 300.0, time = 2 + 3 * u;
    const State st = at(f, time);
    EXPECT_NEAR(st.q[0], s(u), 1e-12) << "u " << u;
    EXPECT_NEAR(st.q[1], 1.0 - 0.5 * s(u), 1e-12) << "u " << u;
    if (i == 0 || i == 300) continue;  // held outside, at rest on the knots
    EXPECT_NEAR(st.qd[0], ds(u) / 3, 1e-12) << "u " << u;
    EXPECT_NEAR(st.qd[1], -0.5 * ds(u) / 3, 1e-12) << "u " << u;
    EXPECT_NEAR(st.qdd[0], dds(u) / 9, 1e-11) << "u " << u;
    EXPECT_NEAR(st.qdd[1], -0.5 * dds(u) / 9, 1e-11) << "u " << u;
  }
}

TEST(SplineTrajectory, TwoKnotsGiveTheSmoothStep) {
  // Only one cubic joins two points at rest: q0 + (q1 - q0)(3u^2 - 2u^3).
  Eigen::VectorXd t(2);
  t << -1.0, 1.5;
  Eigen::MatrixXd q(2, 2);
  q << 0.4, -2.0,  //
      1.0, 3.0;
  const JointTrajectory f = spline_trajectory(t, q);
  const double T = 2.5;
  for (int i = 1; i < 50; ++i) {
    const double u = i / 50.0;
    const State s = at(f, -1.0 + T * u);
    for (int j = 0; j < 2; ++j) {
      const double d = q(1, j) - q(0, j);
      EXPECT_NEAR(s.q[j], q(0, j) + d * (3 * u * u - 2 * u * u * u), 1e-12) << u;
      EXPECT_NEAR(s.qd[j], d * (6 * u - 6 * u * u) / T, 1e-12) << u;
      EXPECT_NEAR(s.qdd[j], d * (6 - 12 * u) / (T * T), 1e-12) << u;
    }
  }
  EXPECT_EQ(at(f, -1.0).q, q.row(0).transpose());
  EXPECT_EQ(at(f, 1.5).q, q.row(1).transpose());
}

TEST(SplineTrajectory, OneKnotIsAConstant) {
  Eigen::VectorXd t(1);
  t << 0.7;
  Eigen::MatrixXd q(1, 3);
  q << 0.1, -0.2, 0.3;
  const JointTrajectory f = spline_trajectory(t, q);
  for (double time : {-5.0, 0.0, 0.7, 0.7000001, 2.0, 100.0}) {
    const State s = at(f, time);
    EXPECT_EQ(s.q, q.row(0).transpose()) << time;
    EXPECT_EQ(s.qd, Eigen::VectorXd::Zero(3)) << time;
    EXPECT_EQ(s.qdd, Eigen::VectorXd::Zero(3)) << time;
  }
}

TEST(SplineTrajectory, JointsAreSplinedIndependently) {
  // All columns at once give what each column alone gives.
  const Knots k;
  const JointTrajectory all = spline_trajectory(k.t, k.q);
  std::vector<JointTrajectory> single;
  for (Eigen::Index j = 0; j < k.q.cols(); ++j)
    single.push_back(spline_trajectory(k.t, k.q.col(j)));
  for (double time : inner_times(k.t, 5, 0.0)) {
    const State s = at(all, time);
    for (Eigen::Index j = 0; j < k.q.cols(); ++j) {
      const State one = at(single[static_cast<std::size_t>(j)], time);
      ASSERT_EQ(one.q.size(), 1);
      EXPECT_NEAR(s.q[j], one.q[0], 1e-14) << time;
      EXPECT_NEAR(s.qd[j], one.qd[0], 1e-13) << time;
      EXPECT_NEAR(s.qdd[j], one.qdd[0], 1e-12) << time;
    }
  }
}

TEST(SplineTrajectory, BadInputThrows) {
  Eigen::MatrixXd q3(3, 2);
  q3.setRandom();
  Eigen::VectorXd t(3);
  t << 0.0, 1.0, 1.0;  // repeated time
  EXPECT_THROW(spline_trajectory(t, q3), InputError);
  t << 0.0, 2.0, 1.0;  // decreasing
  EXPECT_THROW(spline_trajectory(t, q3), InputError);
  t << 0.0, 1.0, std::nan("");
  EXPECT_THROW(spline_trajectory(t, q3), InputError);
  t << 0.0, 1.0, 2.0;
  EXPECT_NO_THROW(spline_trajectory(t, q3));
  EXPECT_THROW(spline_trajectory(t, Eigen::MatrixXd::Zero(2, 2)), InputError);
  EXPECT_THROW(spline_trajectory(t, Eigen::MatrixXd::Zero(4, 2)), InputError);
  EXPECT_THROW(spline_trajectory(Eigen::VectorXd(0), Eigen::MatrixXd(0, 2)), InputError);
}

// ---------------------------------------------------------------- smooth_maneuver

TEST(SmoothManeuver, PumaSwingsOutOneRadianPointTwoAndBack) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  ASSERT_EQ(model.num_joints(), 3);
  const double duration = 4.0;
  const JointTrajectory f = smooth_maneuver(model, duration);

  // Starts at the middle of each range, at rest; ends where it started, at rest.
  const State start = at(f, 0.0), end = at(f, duration);
  for (int j = 0; j < 3; ++j) {
    const Joint& joint = model.joints[static_cast<std::size_t>(j)];
    ASSERT_TRUE(joint.limited);
    EXPECT_NEAR(start.q[j], 0.5 * (joint.lower + joint.upper), 1e-12) << joint.name;
  }
  EXPECT_EQ(start.qd, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(start.qdd, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(end.qd, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(end.qdd, Eigen::VectorXd::Zero(3));
  EXPECT_LT(max_abs(end.q - start.q), 1e-12);
  // Velocity tends to zero at both ends.
  EXPECT_LT(max_abs(at(f, 1e-9).qd), 1e-7);
  EXPECT_LT(max_abs(at(f, duration - 1e-9).qd), 1e-7);
  // Held before and after.
  for (double t : {-1.0, duration + 1.0}) {
    const State s = at(f, t);
    EXPECT_LT(max_abs(s.q - start.q), 1e-12) << t;
    EXPECT_EQ(s.qd, Eigen::VectorXd::Zero(3)) << t;
    EXPECT_EQ(s.qdd, Eigen::VectorXd::Zero(3)) << t;
  }

  // Within the limits all along; 1.2 rad out at mid-time, every joint the same way.
  Eigen::VectorXd excursion = Eigen::VectorXd::Zero(3);
  for (int i = 0; i <= 2000; ++i) {
    const State s = at(f, duration * i / 2000.0);
    for (int j = 0; j < 3; ++j) {
      const Joint& joint = model.joints[static_cast<std::size_t>(j)];
      EXPECT_GE(s.q[j], joint.lower) << joint.name;
      EXPECT_LE(s.q[j], joint.upper) << joint.name;
      excursion[j] = std::max(excursion[j], std::abs(s.q[j] - start.q[j]));
    }
  }
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(excursion[j], 1.2, 1e-9) << j;
  const State mid = at(f, duration / 2);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(mid.q[j] - start.q[j], 1.2, 1e-12) << j;
  EXPECT_LT(max_abs(mid.qd), 1e-12);

  std::vector<double> times;
  for (int i = 1; i < 40; ++i) times.push_back(duration * i / 40.0);
  expect_consistent_derivatives(f, times);
}

TEST(SmoothManeuver, AmplitudeFollowsTheJointTypeAndRange) {
  // A narrow revolute joint (range 1 rad: 0.45 rad), a prismatic one (range
  // 0.4 m: a quarter, 0.1 m) and a continuous one (no limits: 1.2 rad about 0).
  const std::string urdf = R"(<?xml version="1.0"?>
<robot name="mixed">
  <link name="sensor"/>
  <joint name="narrow" type="revolute">
    <parent link="sensor"/><child link="a"/>
    <axis xyz="0 0 1"/><limit lower="0.2" upper="1.2" effort="1" velocity="1"/>
  </joint>
  <link name="a"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="slide" type="prismatic">
    <parent link="a"/><child link="b"/>
    <axis xyz="1 0 0"/><limit lower="-0.1" upper="0.3" effort="1" velocity="1"/>
  </joint>
  <link name="b"><inertial><origin xyz="0 0.1 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="spin" type="continuous">
    <parent link="b"/><child link="c"/>
    <axis xyz="0 1 0"/>
  </joint>
  <link name="c"><inertial><origin xyz="0 0 0.1"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
</robot>
)";
  const Model model = load_urdf_string(urdf);
  ASSERT_EQ(model.num_joints(), 3);
  const double duration = 2.0;
  const JointTrajectory f = smooth_maneuver(model, duration);
  const State start = at(f, 0.0), mid = at(f, duration / 2);
  const Eigen::Vector3d mids(0.7, 0.1, 0.0), amps(0.45, 0.1, 1.2);
  for (int j = 0; j < 3; ++j) {
    const std::string& name = model.joints[static_cast<std::size_t>(j)].name;
    EXPECT_NEAR(start.q[j], mids[j], 1e-12) << name;
    EXPECT_NEAR(mid.q[j] - start.q[j], amps[j], 1e-12) << name;
  }
  std::vector<double> times;
  for (int i = 1; i < 20; ++i) times.push_back(duration * i / 20.0);
  expect_consistent_derivatives(f, times);
}

}  // namespace
}  // namespace massid::emulator

// Stewart platform kinematics: inverse/forward kinematics, the leg Jacobian,
// limit checks, the default geometry's workspace and the geometry file.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "massid/core/errors.hpp"
#include "massid/emulator/stewart_platform.hpp"

namespace massid::emulator {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

Eigen::Isometry3d pose_from_home(const PlatformGeometry& g, const Eigen::Vector3d& translation,
                                 const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d pose = g.home;
  pose.translation() += translation;
  pose.linear() = rotation_from_rpy(rpy) * g.home.linear();
  return pose;
}

// A random pose within the default workspace (translation box, tilt <= 25 deg).
Eigen::Isometry3d random_workspace_pose(const PlatformGeometry& g, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d t(unit(rng), unit(rng), unit(rng));
  Eigen::Vector3d axis(unit(rng), unit(rng), unit(rng));
  axis.normalize();
  const double angle = std::abs(unit(rng)) * g.workspace.max_tilt;
  Eigen::Isometry3d pose = g.home;
  pose.translation() += t.cwiseProduct(g.workspace.max_translation);
  pose.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * g.home.linear();
  return pose;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("massid_stewart_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
           "_" + name))
      .string();
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string input_error(const std::string& text) {
  const std::string path = write_temp("bad.json", text);
  try {
    load_geometry(path);
  } catch (const InputError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  ADD_FAILURE() << "no InputError for: " << text;
  return "";
}

TEST(StewartPlatform, DefaultGeometryIsSemiRegular) {
  const PlatformGeometry g = default_geometry();
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_NEAR(g.base_anchors[i].head<2>().norm(), 0.5, 1e-15);
    EXPECT_NEAR(g.platform_anchors[i].head<2>().norm(), 0.35, 1e-15);
  }
  // Pairs 20 degrees apart on both rings.
  EXPECT_NEAR(std::acos(g.base_anchors[0].normalized().dot(g.base_anchors[1].normalized())),
              20 * kDeg, 1e-12);
  EXPECT_NEAR(std::acos(g.base_anchors[1].normalized().dot(g.base_anchors[2].normalized())),
              100 * kDeg, 1e-12);
  EXPECT_NEAR(std::acos(g.platform_anchors[1].normalized().dot(g.platform_anchors[2].normalized())),
              20 * kDeg, 1e-12);
  EXPECT_EQ(g.home.translation(), Eigen::Vector3d(0, 0, 0.65));
  EXPECT_TRUE(g.home.linear().isIdentity(0.0));
  EXPECT_EQ(g.leg_min, LegVector::Constant(0.55));
  EXPECT_EQ(g.leg_max, LegVector::Constant(0.95));
}

TEST(StewartPlatform, HomeLegsWithinLimitsWithMargin) {
  const PlatformGeometry g = default_geometry();
  const LegVector l = leg_lengths(g, g.home);
  for (int i = 1; i < kNumLegs; ++i) EXPECT_NEAR(l[i], l[0], 1e-14);  // symmetric
  EXPECT_TRUE(legs_within_limits(g, l, 0.1));
  EXPECT_GT(leg_limit_margin(g, l), 0.1);
  EXPECT_TRUE(within_workspace(g, g.home));
  EXPECT_TRUE(pose_reachable(g, g.home, 0.1));
}

TEST(StewartPlatform, DefaultWorkspaceReachable) {
  const PlatformGeometry g = default_geometry();
  const double tilt = 25 * kDeg, shift = 0.15;
  // Each axis alone, 4 cm inside every stroke.
  double worst = 1.0;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d t = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
      t[axis] = sign * shift;
      rpy[axis] = sign * tilt;
      for (const Eigen::Isometry3d& pose : {pose_from_home(g, t, Eigen::Vector3d::Zero()),
                                            pose_from_home(g, Eigen::Vector3d::Zero(), rpy)}) {
        EXPECT_TRUE(pose_reachable(g, pose, 0.04))
            << "translation " << t.transpose() << " or rpy " << rpy.transpose();
        worst = std::min(worst, leg_limit_margin(g, leg_lengths(g, pose)));
      }
    }
  RecordProperty("single_axis_margin_mm", std::to_string(worst * 1e3));
  // 25 degrees about any axis at home.
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  double worst_rotation = 1.0;
  for (int n = 0; n < 1000; ++n) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    Eigen::Isometry3d pose = g.home;
    pose.linear() = Eigen::AngleAxisd(tilt, axis).toRotationMatrix() * g.home.linear();
    worst_rotation = std::min(worst_rotation, leg_limit_margin(g, leg_lengths(g, pose)));
  }
  EXPECT_GT(worst_rotation, 0.0);
  RecordProperty("any_axis_rotation_margin_mm", std::to_string(worst_rotation * 1e3));
  // Every translation within 0.12 m per axis. With the home rotation, leg i is
  // |p - c_i| with c_i = b_i - R_home a_i, convex in p: its maximum over the box
  // is at a corner and its minimum is the distance from c_i to the box.
  const Eigen::Vector3d lo = g.home.translation().array() - 0.12;
  const Eigen::Vector3d hi = g.home.translation().array() + 0.12;
  for (int i = 0; i < kNumLegs; ++i) {
    const Eigen::Vector3d c = g.base_anchors[i] - g.home.linear() * g.platform_anchors[i];
    EXPECT_GE((c.cwiseMax(lo).cwiseMin(hi) - c).norm(), g.leg_min[i]) << i;
  }
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d t(c & 1 ? 0.12 : -0.12, c & 2 ? 0.12 : -0.12, c & 4 ? 0.12 : -0.12);
    EXPECT_LE(leg_lengths(g, pose_from_home(g, t, Eigen::Vector3d::Zero())).maxCoeff(),
              g.leg_max[0]);
  }
  // But not every workspace pose is reachable: a corner of the box, tilted.
  const Eigen::Isometry3d corner = pose_from_home(g, {0.15, 0.15, -0.15}, {tilt, 0, 0});
  EXPECT_TRUE(within_workspace(g, corner));
  EXPECT_FALSE(pose_reachable(g, corner));
}

TEST(StewartPlatform, LimitChecksDetectViolations) {
  const PlatformGeometry g = default_geometry();
  // Straight down by 0.25 m: legs shorter than their 0.55 m minimum.
  const Eigen::Isometry3d low = pose_from_home(g, {0, 0, -0.25}, Eigen::Vector3d::Zero());
  const LegVector l = leg_lengths(g, low);
  EXPECT_LT(l.maxCoeff(), g.leg_min[0]);
  EXPECT_FALSE(legs_within_limits(g, l));
  EXPECT_LT(leg_limit_margin(g, l), 0.0);
  EXPECT_NEAR(leg_limit_margin(g, l), l.minCoeff() - g.leg_min[0], 1e-15);
  EXPECT_FALSE(pose_reachable(g, low));
  EXPECT_FALSE(within_workspace(g, low));  // also outside the 0.15 m box
  // Straight up: beyond the maximum.
  const LegVector high = leg_lengths(g, pose_from_home(g, {0, 0, 0.4}, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(legs_within_limits(g, high));
  EXPECT_NEAR(leg_limit_margin(g, high), g.leg_max[0] - high.maxCoeff(), 1e-15);
  // The margin argument: one leg 5 mm inside its stroke passes with margin 4 mm
  // and fails with 6 mm.
  LegVector near = leg_lengths(g, g.home);
  near[3] = g.leg_max[3] - 0.005;
  EXPECT_NEAR(leg_limit_margin(g, near), 0.005, 1e-15);
  EXPECT_TRUE(legs_within_limits(g, near, 0.004));
  EXPECT_FALSE(legs_within_limits(g, near, 0.006));
  // Per-leg limits are honoured.
  PlatformGeometry tight = g;
  tight.leg_max[2] = leg_lengths(g, g.home)[2] - 1e-3;
  EXPECT_FALSE(legs_within_limits(tight, leg_lengths(g, g.home)));
}

TEST(StewartPlatform, WorkspaceCheck) {
  const PlatformGeometry g = default_geometry();
  EXPECT_TRUE(within_workspace(g, pose_from_home(g, {0.149, -0.149, 0.149}, {0, 0, 0})));
  EXPECT_FALSE(within_workspace(g, pose_from_home(g, {0.151, 0, 0}, {0, 0, 0})));
  EXPECT_FALSE(within_workspace(g, pose_from_home(g, {0, 0, -0.151}, {0, 0, 0})));
  EXPECT_TRUE(within_workspace(g, pose_from_home(g, {0, 0, 0}, {24.9 * kDeg, 0, 0})));
  EXPECT_FALSE(within_workspace(g, pose_from_home(g, {0, 0, 0}, {0, 0, 25.1 * kDeg})));
  const Eigen::Isometry3d p = pose_from_home(g, {0.1, 0, 0}, {0, 20 * kDeg, 0});
  EXPECT_NEAR(tilt_from_home(g, p), 20 * kDeg, 1e-14);
  EXPECT_TRUE(translation_from_home(g, p).isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-15));
}

TEST(StewartPlatform, InverseForwardRoundTrip) {
  const PlatformGeometry g = default_geometry();
  std::mt19937 rng(7);
  int checked = 0, max_iterations = 0;
  for (int n = 0; n < 1000; ++n) {
    const Eigen::Isometry3d pose = random_workspace_pose(g, rng);
    const LegVector l = leg_lengths(g, pose);
    if (!legs_within_limits(g, l)) continue;  // not every workspace pose is reachable
    const ForwardKinematicsResult fk = forward_kinematics(g, l, g.home);
    ASSERT_TRUE(fk.converged) << n << " residual " << fk.residual;
    EXPECT_LE(fk.residual, 1e-12);
    EXPECT_LE((fk.pose.translation() - pose.translation()).norm(), 1e-10) << n;
    EXPECT_LE((fk.pose.linear() - pose.linear()).norm(), 1e-10) << n;
    max_iterations = std::max(max_iterations, fk.iterations);
    ++checked;
  }
  EXPECT_GE(checked, 300);
  EXPECT_LE(max_iterations, 20);
  RecordProperty("round_trips", checked);
  RecordProperty("max_newton_iterations_from_home", max_iterations);
}

TEST(StewartPlatform, ForwardKinematicsTracksFromPreviousPose) {
  const PlatformGeometry g = default_geometry();
  // A smooth path sampled at 1 kHz: from the previous pose Newton needs few steps.
  Eigen::Isometry3d previous = g.home;
  int max_iterations = 0;
  for (int k = 1; k <= 1000; ++k) {
    const double t = k * 1e-3;
    const Eigen::Isometry3d pose =
        pose_from_home(g, {0.1 * std::sin(2 * t), 0.05 * std::sin(3 * t), 0.08 * std::sin(t)},
                       {0.3 * std::sin(5 * t), 0.2 * std::sin(4 * t), 0.1 * t});
    const ForwardKinematicsResult fk = forward_kinematics(g, leg_lengths(g, pose), previous);
    ASSERT_TRUE(fk.converged) << k;
    EXPECT_LE((fk.pose.translation() - pose.translation()).norm(), 1e-10);
    max_iterations = std::max(max_iterations, fk.iterations);
    previous = fk.pose;
  }
  EXPECT_LE(max_iterations, 3);
}

TEST(StewartPlatform, ForwardKinematicsConvergesFromHome) {
  const PlatformGeometry g = default_geometry();
  // Home itself: zero steps.
  const ForwardKinematicsResult at_home = forward_kinematics(g, leg_lengths(g, g.home), g.home);
  EXPECT_TRUE(at_home.converged);
  EXPECT_EQ(at_home.iterations, 0);
  EXPECT_LE(at_home.residual, 1e-12);
  // A far pose: edge of the workspace.
  const Eigen::Isometry3d pose =
      pose_from_home(g, {0.15, -0.15, 0.1}, {15 * kDeg, -15 * kDeg, 10 * kDeg});
  const ForwardKinematicsResult fk = forward_kinematics(g, leg_lengths(g, pose), g.home);
  ASSERT_TRUE(fk.converged);
  EXPECT_GT(fk.iterations, 0);
  EXPECT_LE(fk.iterations, ForwardKinematicsOptions{}.max_iterations);
  EXPECT_LE(fk.residual, 1e-12);
  EXPECT_TRUE(fk.pose.isApprox(pose, 1e-10));
}

TEST(StewartPlatform, ForwardKinematicsFailsGracefully) {
  const PlatformGeometry g = default_geometry();
  // Lengths no pose can have: leg 0 far longer than its neighbour allows.
  LegVector impossible = leg_lengths(g, g.home);
  impossible[0] = 3.0;
  const ForwardKinematicsResult fk = forward_kinematics(g, impossible, g.home);
  EXPECT_FALSE(fk.converged);
  EXPECT_GT(fk.residual, 1e-6);
  EXPECT_TRUE(fk.pose.matrix().allFinite());
  // Too few iterations for a far pose.
  const Eigen::Isometry3d pose = pose_from_home(g, {0.15, 0.15, 0.15}, {0.4, 0, 0});
  ForwardKinematicsOptions few;
  few.max_iterations = 2;
  const ForwardKinematicsResult short_run =
      forward_kinematics(g, leg_lengths(g, pose), g.home, few);
  EXPECT_FALSE(short_run.converged);
  EXPECT_LE(short_run.iterations, 2);
  // Non-finite input.
  LegVector nan = leg_lengths(g, g.home);
  nan[1] = std::nan("");
  EXPECT_FALSE(forward_kinematics(g, nan, g.home).converged);
}

TEST(StewartPlatform, JacobianMatchesFiniteDifferences) {
  const PlatformGeometry g = default_geometry();
  std::mt19937 rng(11);
  const double h = 1e-6;
  for (int n = 0; n < 20; ++n) {
    const Eigen::Isometry3d pose = random_workspace_pose(g, rng);
    const PlatformJacobian J = platform_jacobian(g, pose);
    PlatformJacobian numeric;
    for (int k = 0; k < 6; ++k) {
      Twist d = Twist::Zero();
      d[k] = h;
      numeric.col(k) =
          (leg_lengths(g, apply_twist(pose, d)) - leg_lengths(g, apply_twist(pose, -d))) / (2 * h);
    }
    EXPECT_LE((J - numeric).cwiseAbs().maxCoeff(), 1e-8) << n;
  }
}

TEST(StewartPlatform, JacobianTransposeIsStatics) {
  // Virtual work: leg forces tau do work tau . dl = (J^T tau) . twist.
  const PlatformGeometry g = default_geometry();
  const Eigen::Isometry3d pose = pose_from_home(g, {0.05, 0.02, -0.03}, {0.1, -0.2, 0.3});
  const LegState legs = inverse_kinematics(g, pose);
  const PlatformJacobian J = platform_jacobian(legs);
  LegVector tau;
  tau << 10, -20, 30, 5, 15, -8;
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  for (int i = 0; i < kNumLegs; ++i) {
    f += tau[i] * legs.direction.col(i);
    m += legs.arm.col(i).cross(tau[i] * legs.direction.col(i));
  }
  const Twist wrench = J.transpose() * tau;
  EXPECT_TRUE(wrench.head<3>().isApprox(f, 1e-14));
  EXPECT_TRUE(wrench.tail<3>().isApprox(m, 1e-14));
}

TEST(StewartPlatform, RpyRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), pitch(-1.5, 1.5);
  for (int n = 0; n < 100; ++n) {
    const Eigen::Vector3d rpy(angle(rng), pitch(rng), angle(rng));
    EXPECT_TRUE(rpy_from_rotation(rotation_from_rpy(rpy)).isApprox(rpy, 1e-12));
  }
  // URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Matrix3d R = rotation_from_rpy({0.1, 0.2, 0.3});
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(R.isApprox(expected, 1e-15));
}

void expect_same_geometry(const PlatformGeometry& a, const PlatformGeometry& b) {
  for (int i = 0; i < kNumLegs; ++i) {
    EXPECT_EQ(a.base_anchors[i], b.base_anchors[i]) << i;
    EXPECT_EQ(a.platform_anchors[i], b.platform_anchors[i]) << i;
  }
  EXPECT_EQ(a.leg_min, b.leg_min);
  EXPECT_EQ(a.leg_max, b.leg_max);
  EXPECT_EQ(a.home.translation(), b.home.translation());
  EXPECT_LE((a.home.linear() - b.home.linear()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(a.workspace.max_translation, b.workspace.max_translation);
  EXPECT_NEAR(a.workspace.max_tilt, b.workspace.max_tilt, 1e-15);
}

TEST(StewartPlatform, JsonRoundTrip) {
  PlatformGeometry g = semi_regular_geometry(0.45, 0.3, 15 * kDeg, 25 * kDeg, 0.55, 0.45, 0.9);
  g.leg_max[4] = 0.92;  // per-leg limits are kept as an array
  g.home.linear() = rotation_from_rpy({0.01, -0.02, 0.5});
  g.workspace.max_translation = {0.1, 0.12, 0.08};
  g.workspace.max_tilt = 20 * kDeg;
  const std::string path = temp_path("roundtrip.json");
  save_geometry(path, g);
  const PlatformGeometry loaded = load_geometry(path);
  std::filesystem::remove(path);
  expect_same_geometry(g, loaded);
  // And the default geometry.
  expect_same_geometry(default_geometry(), parse_geometry(geometry_json(default_geometry()), "x"));
}

TEST(StewartPlatform, JsonMissingFieldsTakeDefaults) {
  const PlatformGeometry d = default_geometry();
  expect_same_geometry(d, parse_geometry("{}", "empty.json"));
  const PlatformGeometry g = parse_geometry(
      R"({"leg_max": 1.0, "home": {"position": [0, 0, 0.62]}, "workspace": {"max_tilt_deg": 20}})",
      "partial.json");
  EXPECT_EQ(g.leg_max, LegVector::Constant(1.0));
  EXPECT_EQ(g.leg_min, d.leg_min);
  EXPECT_EQ(g.home.translation(), Eigen::Vector3d(0, 0, 0.62));
  EXPECT_TRUE(g.home.linear().isIdentity(0.0));
  EXPECT_NEAR(g.workspace.max_tilt, 20 * kDeg, 1e-15);
  EXPECT_EQ(g.workspace.max_translation, d.workspace.max_translation);
  EXPECT_EQ(g.base_anchors[3], d.base_anchors[3]);
}

TEST(StewartPlatform, JsonErrors) {
  // Malformed: file:line:col.
  const std::string malformed = input_error("{\n  \"leg_min\": 0.5,\n  \"leg_max\": ]\n}\n");
  EXPECT_NE(malformed.find("bad.json:3:14: malformed JSON"), std::string::npos) << malformed;
  // Wrong types name the field.
  std::string e = input_error(R"({"leg_min": "short"})");
  EXPECT_NE(e.find("bad.json: field 'leg_min'"), std::string::npos) << e;
  e = input_error(R"({"home": {"position": [0, 0, "up"]}})");
  EXPECT_NE(e.find("field 'home.position[2]': expected a number"), std::string::npos) << e;
  e = input_error(R"({"base_anchors": [[0, 0, 0]]})");
  EXPECT_NE(e.find("field 'base_anchors': expected an array of 6"), std::string::npos) << e;
  e = input_error(R"({"platform_anchors": [[0,0,0],[0,0,0],[0,0,0],[0,0,0],[0,0,0],[0,0]]})");
  EXPECT_NE(e.find("field 'platform_anchors[5]'"), std::string::npos) << e;
  e = input_error(R"({"workspace": {"max_tilt_deg": [25]}})");
  EXPECT_NE(e.find("field 'workspace.max_tilt_deg'"), std::string::npos) << e;
  e = input_error(R"({"workspace": 3})");
  EXPECT_NE(e.find("field 'workspace': expected an object"), std::string::npos) << e;
  e = input_error(R"({"format": "massid-params-1"})");
  EXPECT_NE(e.find("field 'format'"), std::string::npos) << e;
  e = input_error("[1, 2]");
  EXPECT_NE(e.find("expected a JSON object"), std::string::npos) << e;
  // Typos are not silently replaced by defaults.
  e = input_error(R"({"leg_mx": 1.0})");
  EXPECT_NE(e.find("field 'leg_mx': unknown field"), std::string::npos) << e;
  e = input_error(R"({"home": {"postion": [0, 0, 0.6]}})");
  EXPECT_NE(e.find("field 'home.postion': unknown field"), std::string::npos) << e;
  // Geometry that cannot work.
  e = input_error(R"({"leg_min": 0.9, "leg_max": 0.8})");
  EXPECT_NE(e.find("field 'leg_max'"), std::string::npos) << e;
  e = input_error(R"({"home": {"position": [0, 0, 1.5]}})");
  EXPECT_NE(e.find("field 'home': leg 0"), std::string::npos) << e;
  // Missing file.
  try {
    load_geometry("/nonexistent/platform.json");
    ADD_FAILURE();
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("/nonexistent/platform.json: cannot open"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace massid::emulator

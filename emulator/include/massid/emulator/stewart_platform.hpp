// Kinematics of a 6-6 Stewart platform (hexapod): six legs of variable length,
// leg i joining base anchor b_i (base frame) to platform anchor a_i (platform
// frame) through spherical/universal joints.
//
//   pose:  the platform frame in the base frame, T = (R, p)
//   leg i: s_i = p + R a_i - b_i,   l_i = |s_i|,   u_i = s_i / l_i
//
// Inverse kinematics is closed form. Forward kinematics (leg lengths -> pose)
// has up to 40 assembly modes; Newton's method from a nearby pose (the previous
// one, or home) tracks the mode the platform is actually in.
//
// Twists are [v; w] (base frame): v the velocity of the platform frame's origin,
// w the angular velocity. The leg-rate Jacobian J (6x6) gives
//
//   dl/dt = J [v; w],   row i = [u_i^T, (R a_i x u_i)^T],
//
// and by statics its transpose maps leg forces to the wrench on the platform
// (about its origin, base-frame axes): [f; m] = J^T tau.
//
// Everything here is fixed-size: no function except the file I/O allocates.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>

namespace massid::emulator {

inline constexpr int kNumLegs = 6;

using LegVector = Eigen::Matrix<double, kNumLegs, 1>;         // one value per leg (m, m/s, N)
using Twist = Eigen::Matrix<double, 6, 1>;                    // [v; w], base frame
using PlatformJacobian = Eigen::Matrix<double, kNumLegs, 6>;  // dl/dt = J twist

// Where the platform may go, relative to its home pose.
struct WorkspaceLimits {
  // |p - p_home| per base-frame axis (m).
  Eigen::Vector3d max_translation = Eigen::Vector3d::Constant(0.15);
  // Angle of the rotation R_home^T R about any axis (rad): bounds tilt and yaw alike.
  double max_tilt = 25.0 * 3.14159265358979323846 / 180.0;
};

// A hexapod's geometry. default_geometry() documents the reference lab platform.
struct PlatformGeometry {
  std::array<Eigen::Vector3d, kNumLegs> base_anchors;      // b_i, base frame (m)
  std::array<Eigen::Vector3d, kNumLegs> platform_anchors;  // a_i, platform frame (m)
  LegVector leg_min = LegVector::Zero();                   // stroke limits per leg (m)
  LegVector leg_max = LegVector::Zero();
  Eigen::Isometry3d home = Eigen::Isometry3d::Identity();  // platform frame in base frame
  WorkspaceLimits workspace;
};

// Semi-regular hexagons: base anchors in pairs about 0, 120 and 240 degrees,
// `base_gap` (rad) apart within a pair; platform anchors in pairs about 60, 180
// and 300 degrees, `platform_gap` apart. Each leg joins a base anchor to the
// nearer anchor of the neighbouring platform pair, so the legs cross in the
// usual zig-zag. Anchors lie in the z = 0 planes of their frames; the home pose
// is a pure lift by `home_height` along base z.
PlatformGeometry semi_regular_geometry(double base_radius, double platform_radius, double base_gap,
                                       double platform_gap, double home_height, double leg_min,
                                       double leg_max);

// The reference lab hexapod, sized to move a ~15 kg arm:
//   base radius 0.5 m, platform radius 0.35 m, anchor pairs 20 deg apart on both
//   rings (100 deg between pairs), home height 0.65 m, legs 0.55 .. 0.95 m (a
//   0.40 m stroke). Every leg is 0.726 m long at home (>= 0.17 m from either
//   end). Workspace: +-0.15 m per axis and 25 deg from home.
//   Reachable (checked in the tests): +-0.15 m along any one axis and +-25 deg
//   of roll, pitch or yaw alone, all legs >= 4 cm inside their strokes; 25 deg
//   about any axis at home; any translation within +-0.12 m per axis. Not every
//   combination is: the box's corners with 25 deg tilts need legs of 0.37 .. 1.11
//   m. So within_workspace() alone does not mean reachable; use pose_reachable().
PlatformGeometry default_geometry();

// Leg lengths and directions at one pose.
struct LegState {
  using Columns = Eigen::Matrix<double, 3, kNumLegs>;
  LegVector length = LegVector::Zero();  // l_i (m)
  Columns direction = Columns::Zero();   // u_i, unit, base frame
  Columns arm = Columns::Zero();         // R a_i, base frame
};

// Inverse kinematics: the legs at `pose` (platform frame in base frame).
LegState inverse_kinematics(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose);
LegVector leg_lengths(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose);

// The leg-rate Jacobian at a pose (see the header comment).
PlatformJacobian platform_jacobian(const LegState& legs);
PlatformJacobian platform_jacobian(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose);

// A pose moved along a twist for unit time: p + v, exp([w]x) R.
Eigen::Isometry3d apply_twist(const Eigen::Isometry3d& pose, const Twist& twist);

struct ForwardKinematicsOptions {
  double tolerance = 1e-12;  // converged when max_i |l_i(pose) - l_i| <= tolerance (m)
  int max_iterations = 50;
  double max_step_translation = 0.05;  // Newton steps are scaled down to at most this (m)
  double max_step_rotation = 0.2;      // and this (rad), which keeps far guesses on track
};

struct ForwardKinematicsResult {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // the last iterate
  bool converged = false;
  int iterations = 0;     // Newton steps taken
  double residual = 0.0;  // max_i |l_i(pose) - l_i| at `pose` (m)
};

// Forward kinematics: the pose with the given leg lengths, by Newton's method
// with the analytic Jacobian, starting at `guess`. Not converging (a singular
// Jacobian, the iteration limit, non-finite values) is reported through
// `converged`, never thrown; `pose` is then the best iterate found.
ForwardKinematicsResult forward_kinematics(const PlatformGeometry& geometry,
                                           const LegVector& lengths, const Eigen::Isometry3d& guess,
                                           const ForwardKinematicsOptions& options = {});

// Distance of the nearest leg to either end of its stroke (m), the minimum over
// legs of min(l_i - min_i, max_i - l_i). Negative when a leg is out of range.
double leg_limit_margin(const PlatformGeometry& geometry, const LegVector& lengths);

// Every leg at least `margin` inside its stroke: min_i + margin <= l_i <= max_i - margin.
bool legs_within_limits(const PlatformGeometry& geometry, const LegVector& lengths,
                        double margin = 0.0);

// The pose's rotation angle from home (rad) and translation from home (m, base frame).
double tilt_from_home(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose);
Eigen::Vector3d translation_from_home(const PlatformGeometry& geometry,
                                      const Eigen::Isometry3d& pose);

// The pose lies within geometry.workspace. Poses on its boundary count as
// inside up to kWorkspaceTolerance (m and rad), so that home + 0.15 m passes.
inline constexpr double kWorkspaceTolerance = 1e-9;
bool within_workspace(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose);

// Both: within the workspace, and legs at least `margin` inside their strokes.
bool pose_reachable(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose,
                    double margin = 0.0);

// Roll-pitch-yaw as in URDF: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d rotation_from_rpy(const Eigen::Vector3d& rpy);
Eigen::Vector3d rpy_from_rotation(const Eigen::Matrix3d& rotation);

// The geometry file (JSON, "massid-platform-1"):
//   {"format": "massid-platform-1",
//    "base_anchors": [[x, y, z] x 6], "platform_anchors": [[x, y, z] x 6],
//    "leg_min": 0.5, "leg_max": 0.95,            (or arrays of 6)
//    "home": {"position": [x, y, z], "rpy": [r, p, y]},          (rad)
//    "workspace": {"max_translation": 0.15,      (or [x, y, z])
//                  "max_tilt_deg": 25}}
// Lengths in metres. Missing fields take default_geometry()'s values; unknown
// fields are errors (a typo would otherwise silently fall back to a default).
std::string geometry_json(const PlatformGeometry& geometry);

// Reads a geometry file. InputError names the file and the field at fault, or
// file:line:column for malformed JSON, and rejects geometry that cannot work
// (leg_min >= leg_max, the home pose outside the strokes, non-finite values).
PlatformGeometry load_geometry(const std::string& path);

// The same from JSON text; `source` names it in messages.
PlatformGeometry parse_geometry(const std::string& text, const std::string& source);

// Writes geometry_json() to `path` atomically; InputError when it cannot.
void save_geometry(const std::string& path, const PlatformGeometry& geometry);

}  // namespace massid::emulator

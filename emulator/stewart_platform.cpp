#include "massid/emulator/stewart_platform.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/json_text.hpp"
#include "massid/core/errors.hpp"

namespace massid::emulator {
namespace {

using json = nlohmann::ordered_json;
constexpr const char* kFormat = "massid-platform-1";
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Thrown by the field readers and turned into an InputError naming the file.
struct FieldError {
  std::string field, what;
};

double read_number(const json& j, const std::string& field) {
  if (!j.is_number()) throw FieldError{field, "expected a number"};
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw FieldError{field, "expected a finite number"};
  return v;
}

Eigen::Vector3d read_vector3(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() != 3) throw FieldError{field, "expected an array [x, y, z]"};
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) v[k] = read_number(j[k], fmt::format("{}[{}]", field, k));
  return v;
}

std::array<Eigen::Vector3d, kNumLegs> read_anchors(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() != kNumLegs)
    throw FieldError{field, "expected an array of 6 points [x, y, z]"};
  std::array<Eigen::Vector3d, kNumLegs> out;
  for (int i = 0; i < kNumLegs; ++i) out[i] = read_vector3(j[i], fmt::format("{}[{}]", field, i));
  return out;
}

// A number for all legs, or an array of six.
LegVector read_legs(const json& j, const std::string& field) {
  if (j.is_number()) return LegVector::Constant(read_number(j, field));
  if (!j.is_array() || j.size() != kNumLegs)
    throw FieldError{field, "expected a number or an array of 6 numbers"};
  LegVector v;
  for (int i = 0; i < kNumLegs; ++i) v[i] = read_number(j[i], fmt::format("{}[{}]", field, i));
  return v;
}

void check_keys(const json& j, const std::string& prefix,
                std::initializer_list<const char*> known) {
  for (const auto& item : j.items()) {
    const std::string& key = item.key();
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return key == k; }))
      throw FieldError{prefix + key, "unknown field"};
  }
}

const json& object_field(const json& j, const char* key, const std::string& field) {
  const json& o = j.at(key);
  if (!o.is_object()) throw FieldError{field, "expected an object"};
  return o;
}

json vector_json(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json legs_json(const LegVector& v) {
  if ((v.array() == v[0]).all()) return v[0];
  json out = json::array();
  for (int i = 0; i < kNumLegs; ++i) out.push_back(v[i]);
  return out;
}

void check_geometry(const PlatformGeometry& g) {
  for (int i = 0; i < kNumLegs; ++i) {
    if (!(g.leg_min[i] > 0.0))
      throw FieldError{"leg_min",
                       fmt::format("leg {} has a non-positive minimum length {}", i, g.leg_min[i])};
    if (!(g.leg_max[i] > g.leg_min[i]))
      throw FieldError{"leg_max", fmt::format("leg {}: maximum length {} is not above the "
                                              "minimum {}",
                                              i, g.leg_max[i], g.leg_min[i])};
  }
  if (!(g.workspace.max_translation.array() >= 0.0).all())
    throw FieldError{"workspace.max_translation", "must not be negative"};
  if (!(g.workspace.max_tilt >= 0.0 && g.workspace.max_tilt <= kPi))
    throw FieldError{"workspace.max_tilt_deg", "must lie in [0, 180]"};
  const LegState legs = inverse_kinematics(g, g.home);
  for (int i = 0; i < kNumLegs; ++i)
    if (!(legs.length[i] >= g.leg_min[i] && legs.length[i] <= g.leg_max[i]))
      throw FieldError{"home", fmt::format("leg {} is {:.4f} m long at home, outside its stroke "
                                           "[{}, {}]",
                                           i, legs.length[i], g.leg_min[i], g.leg_max[i])};
  const Eigen::PartialPivLU<PlatformJacobian> lu(platform_jacobian(legs));
  if (!(lu.rcond() > 1e-9))
    throw FieldError{"home", "the platform is singular at home (the leg Jacobian has rank < 6)"};
}

}  // namespace

PlatformGeometry semi_regular_geometry(double base_radius, double platform_radius, double base_gap,
                                       double platform_gap, double home_height, double leg_min,
                                       double leg_max) {
  PlatformGeometry g;
  for (int pair = 0; pair < 3; ++pair) {
    const double base_center = pair * 120.0 * kDeg;
    // Leg 2*pair and 2*pair+1 start at the pair centred on base_center; they end
    // on the platform pairs centred 60 degrees before and after it.
    const double b0 = base_center - base_gap / 2, b1 = base_center + base_gap / 2;
    const double p0 = base_center - 60.0 * kDeg + platform_gap / 2;
    const double p1 = base_center + 60.0 * kDeg - platform_gap / 2;
    g.base_anchors[2 * pair] = {base_radius * std::cos(b0), base_radius * std::sin(b0), 0.0};
    g.base_anchors[2 * pair + 1] = {base_radius * std::cos(b1), base_radius * std::sin(b1), 0.0};
    g.platform_anchors[2 * pair] = {platform_radius * std::cos(p0), platform_radius * std::sin(p0),
                                    0.0};
    g.platform_anchors[2 * pair + 1] = {platform_radius * std::cos(p1),
                                        platform_radius * std::sin(p1), 0.0};
  }
  g.leg_min = LegVector::Constant(leg_min);
  g.leg_max = LegVector::Constant(leg_max);
  g.home = Eigen::Isometry3d::Identity();
  g.home.translation() = Eigen::Vector3d(0.0, 0.0, home_height);
  return g;
}

PlatformGeometry default_geometry() {
  return semi_regular_geometry(0.5, 0.35, 20.0 * kDeg, 20.0 * kDeg, 0.65, 0.55, 0.95);
}

LegState inverse_kinematics(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose) {
  LegState s;
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d p = pose.translation();
  for (int i = 0; i < kNumLegs; ++i) {
    const Eigen::Vector3d arm = R * geometry.platform_anchors[i];
    const Eigen::Vector3d leg = p + arm - geometry.base_anchors[i];
    const double l = leg.norm();
    s.length[i] = l;
    s.direction.col(i) = leg / l;
    s.arm.col(i) = arm;
  }
  return s;
}

LegVector leg_lengths(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose) {
  return inverse_kinematics(geometry, pose).length;
}

PlatformJacobian platform_jacobian(const LegState& legs) {
  PlatformJacobian J;
  for (int i = 0; i < kNumLegs; ++i) {
    const Eigen::Vector3d u = legs.direction.col(i);
    J.block<1, 3>(i, 0) = u.transpose();
    J.block<1, 3>(i, 3) = legs.arm.col(i).cross(u).transpose();
  }
  return J;
}

PlatformJacobian platform_jacobian(const PlatformGeometry& geometry,
                                   const Eigen::Isometry3d& pose) {
  return platform_jacobian(inverse_kinematics(geometry, pose));
}

Eigen::Isometry3d apply_twist(const Eigen::Isometry3d& pose, const Twist& twist) {
  Eigen::Isometry3d out = pose;
  out.translation() += twist.head<3>();
  const Eigen::Vector3d w = twist.tail<3>();
  const double angle = w.norm();
  if (angle > 0.0)
    out.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() * pose.linear();
  return out;
}

ForwardKinematicsResult forward_kinematics(const PlatformGeometry& geometry,
                                           const LegVector& lengths, const Eigen::Isometry3d& guess,
                                           const ForwardKinematicsOptions& options) {
  ForwardKinematicsResult best;
  best.pose = guess;
  best.residual = std::numeric_limits<double>::infinity();
  if (!lengths.allFinite() || !guess.matrix().allFinite()) return best;
  Eigen::Isometry3d pose = guess;
  for (int it = 0;; ++it) {
    const LegState legs = inverse_kinematics(geometry, pose);
    const LegVector r = legs.length - lengths;
    const double residual = r.cwiseAbs().maxCoeff();
    if (!std::isfinite(residual)) return best;
    if (residual < best.residual) {
      best.pose = pose;
      best.residual = residual;
      best.iterations = it;
    }
    if (residual <= options.tolerance) {
      best.converged = true;
      return best;
    }
    if (it >= options.max_iterations) return best;
    const Eigen::PartialPivLU<PlatformJacobian> lu(platform_jacobian(legs));
    if (!(lu.rcond() > 1e-13)) return best;  // singular: no unique step
    Twist step = -lu.solve(r);
    const double scale = std::max({1.0, step.head<3>().norm() / options.max_step_translation,
                                   step.tail<3>().norm() / options.max_step_rotation});
    step /= scale;
    pose = apply_twist(pose, step);
    best.iterations = it + 1;
  }
}

double leg_limit_margin(const PlatformGeometry& geometry, const LegVector& lengths) {
  return (lengths - geometry.leg_min).cwiseMin(geometry.leg_max - lengths).minCoeff();
}

bool legs_within_limits(const PlatformGeometry& geometry, const LegVector& lengths, double margin) {
  return ((lengths - geometry.leg_min).array() >= margin).all() &&
         ((geometry.leg_max - lengths).array() >= margin).all();
}

double tilt_from_home(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose) {
  return Eigen::AngleAxisd(geometry.home.linear().transpose() * pose.linear()).angle();
}

Eigen::Vector3d translation_from_home(const PlatformGeometry& geometry,
                                      const Eigen::Isometry3d& pose) {
  return pose.translation() - geometry.home.translation();
}

bool within_workspace(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose) {
  return (translation_from_home(geometry, pose).cwiseAbs().array() <=
          geometry.workspace.max_translation.array() + kWorkspaceTolerance)
             .all() &&
         tilt_from_home(geometry, pose) <= geometry.workspace.max_tilt + kWorkspaceTolerance;
}

bool pose_reachable(const PlatformGeometry& geometry, const Eigen::Isometry3d& pose,
                    double margin) {
  return within_workspace(geometry, pose) &&
         legs_within_limits(geometry, leg_lengths(geometry, pose), margin);
}

Eigen::Matrix3d rotation_from_rpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d rpy_from_rotation(const Eigen::Matrix3d& R) {
  const double c = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), c);
  if (c < 1e-12)  // gimbal lock: only roll - yaw (or roll + yaw) is defined; put it in yaw
    return {0.0, pitch, std::atan2(-R(0, 1), R(1, 1))};
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

std::string geometry_json(const PlatformGeometry& g) {
  json j;
  j["format"] = kFormat;
  json base = json::array(), platform = json::array();
  for (int i = 0; i < kNumLegs; ++i) {
    base.push_back(vector_json(g.base_anchors[i]));
    platform.push_back(vector_json(g.platform_anchors[i]));
  }
  j["base_anchors"] = base;
  j["platform_anchors"] = platform;
  j["leg_min"] = legs_json(g.leg_min);
  j["leg_max"] = legs_json(g.leg_max);
  j["home"] = {{"position", vector_json(g.home.translation())},
               {"rpy", vector_json(rpy_from_rotation(g.home.linear()))}};
  const Eigen::Vector3d& t = g.workspace.max_translation;
  j["workspace"] = {{"max_translation", (t.array() == t[0]).all() ? json(t[0]) : vector_json(t)},
                    {"max_tilt_deg", g.workspace.max_tilt / kDeg}};
  return j.dump(2) + "\n";
}

PlatformGeometry parse_geometry(const std::string& text, const std::string& source) {
  json j = parse_json(text, source);
  PlatformGeometry g = default_geometry();
  try {
    if (!j.is_object())
      throw FieldError{"(top level)", "not a platform geometry file (expected a JSON object)"};
    check_keys(
        j, "",
        {"format", "base_anchors", "platform_anchors", "leg_min", "leg_max", "home", "workspace"});
    if (j.contains("format") && !(j["format"].is_string() && j["format"] == kFormat))
      throw FieldError{"format", fmt::format("expected \"{}\"", kFormat)};
    if (j.contains("base_anchors"))
      g.base_anchors = read_anchors(j["base_anchors"], "base_anchors");
    if (j.contains("platform_anchors"))
      g.platform_anchors = read_anchors(j["platform_anchors"], "platform_anchors");
    if (j.contains("leg_min")) g.leg_min = read_legs(j["leg_min"], "leg_min");
    if (j.contains("leg_max")) g.leg_max = read_legs(j["leg_max"], "leg_max");
    if (j.contains("home")) {
      const json& h = object_field(j, "home", "home");
      check_keys(h, "home.", {"position", "rpy"});
      if (h.contains("position"))
        g.home.translation() = read_vector3(h["position"], "home.position");
      if (h.contains("rpy"))
        g.home.linear() = rotation_from_rpy(read_vector3(h["rpy"], "home.rpy"));
    }
    if (j.contains("workspace")) {
      const json& w = object_field(j, "workspace", "workspace");
      check_keys(w, "workspace.", {"max_translation", "max_tilt_deg"});
      if (w.contains("max_translation")) {
        const json& t = w["max_translation"];
        g.workspace.max_translation =
            t.is_number() ? Eigen::Vector3d::Constant(read_number(t, "workspace.max_translation"))
                          : read_vector3(t, "workspace.max_translation");
      }
      if (w.contains("max_tilt_deg"))
        g.workspace.max_tilt = read_number(w["max_tilt_deg"], "workspace.max_tilt_deg") * kDeg;
    }
    check_geometry(g);
  } catch (const FieldError& e) {
    throw InputError(fmt::format("{}: field '{}': {}", source, e.field, e.what));
  }
  return g;
}

PlatformGeometry load_geometry(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open platform geometry file", path));
  std::ostringstream buf;
  buf << in.rdbuf();
  return parse_geometry(buf.str(), path);
}

void save_geometry(const std::string& path, const PlatformGeometry& geometry) {
  write_file_atomically(path, geometry_json(geometry));
}

}  // namespace massid::emulator

#include "io/column_map.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <iterator>
#include <numbers>
#include <set>

#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::detail {
namespace {

int find(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

const char* const kSensorMotion[9] = {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"};

// "a,b,c" of the first 40 names, then " and N more".
std::string name_list(const std::vector<std::string>& names, const char* separator = ",") {
  constexpr size_t kShown = 40;
  std::string out;
  for (size_t i = 0; i < std::min(names.size(), kShown); ++i)
    out += (i ? separator : "") + names[i];
  if (names.size() > kShown) out += fmt::format(" and {} more", names.size() - kShown);
  return out.empty() ? "no columns" : out;
}

// Columns that must be all present or all absent.
ColumnGroup all_or_none(const std::vector<std::string>& header, const std::string& where,
                        std::initializer_list<const char*> names) {
  ColumnGroup out;
  std::vector<std::string> missing;
  for (const char* n : names) {
    out.push_back({find(header, n), 1.0});
    if (out.back().column < 0) missing.push_back(n);
  }
  if (missing.size() == names.size()) return {};
  if (!missing.empty())
    throw InputError(fmt::format("{}: column(s) {} missing (the header has some of {} but not all)",
                                 where, fmt::join(missing, ","),
                                 fmt::join(names.begin(), names.end(), ",")));
  return out;
}

// joint_column with the suffix for every joint, or none.
ColumnGroup suffixed(const std::vector<Joint>& joints, const std::vector<std::string>& header,
                     const std::string& where, const char* suffix) {
  ColumnGroup out;
  std::vector<std::string> missing;
  for (const Joint& j : joints) {
    out.push_back(joint_column(j, header, suffix));
    if (out.back().column < 0) missing.push_back(j.name + suffix);
  }
  if (missing.size() == joints.size()) return {};
  if (!missing.empty())
    throw InputError(
        fmt::format("{}: column(s) {} missing (the header has {} columns for some "
                    "joints but not all)",
                    where, fmt::join(missing, ","), suffix));
  return out;
}

// A role the header has: bound, or a column of its name not bound to another role.
bool has_role(const std::vector<std::string>& header, const ColumnNames& names,
              const std::string& role) {
  const bool bound = std::any_of(names.bind.begin(), names.bind.end(),
                                 [&](const auto& b) { return b.first == role; });
  const bool elsewhere = std::any_of(names.bind.begin(), names.bind.end(), [&](const auto& b) {
    return b.second == role && b.first != role;
  });
  return bound || (find(header, role) >= 0 && !elsewhere);
}

bool is_pose_role(const std::string& role) {
  const auto in = [&](const auto& group) {
    return std::any_of(std::begin(group), std::end(group),
                       [&](const char* n) { return role == n; });
  };
  return in(kPoseQuaternion) || in(kPoseMatrix) || in(kPosePosition);
}

// The roles a column can be bound to: the fixed ones, then every joint's.
bool is_role(const Model& model, const std::string& role) {
  static const std::set<std::string> fixed = {
      "fx", "fy", "fz", "mx",  "my",  "mz",  "gx", "gy", "gz", "t",          "block",
      "wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az", "tilt_x_deg", "tilt_y_deg"};
  if (fixed.count(role) || is_pose_role(role)) return true;
  for (const auto* joints : {&model.joints, &model.upstream_joints})
    for (const Joint& j : *joints)
      if (role == j.name || role == j.name + "_vel" || role == j.name + "_acc" ||
          (j.type == JointType::Revolute &&
           (role == j.name + "_deg" || role == j.name + "_deg_vel" || role == j.name + "_deg_acc")))
        return true;
  return false;
}

// "fx=A,fy=B,..." for the wrench: the column read as each role, else NAME.
std::string wrench_proposal(const std::vector<std::string>& header,
                            const std::vector<std::string>& roles, const int (&candidate)[6]) {
  std::string out;
  for (int k = 0; k < 6; ++k) {
    const int c = find(roles, kWrenchColumns[k]);
    const int col = c >= 0 ? c : candidate[k];
    out += fmt::format("{}{}={}", k ? "," : "", kWrenchColumns[k], col >= 0 ? header[col] : "NAME");
  }
  return out;
}

}  // namespace

BoundColumn joint_column(const Joint& j, const std::vector<std::string>& header,
                         const std::string& suffix) {
  BoundColumn b{find(header, j.name + suffix), 1.0};
  if (b.column < 0 && j.type == JointType::Revolute)
    b = {find(header, j.name + "_deg" + suffix), std::numbers::pi / 180.0};
  return b;
}

int wrench_spelling(const std::string& name) {
  // Tokens of the lower-cased name, split at . / _ - and blanks.
  std::vector<std::string> tokens(1);
  for (const char ch : name) {
    if (ch == '.' || ch == '/' || ch == '_' || ch == '-' || ch == ' ') {
      if (!tokens.back().empty()) tokens.emplace_back();
    } else {
      tokens.back() += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    }
  }
  if (tokens.back().empty()) tokens.pop_back();
  const auto axis = [](const std::string& a) {
    return a.size() == 1 && a[0] >= 'x' && a[0] <= 'z' ? a[0] - 'x' : -1;
  };
  if (tokens.size() == 1 && tokens[0].size() == 2) {  // Fx, FX, tx, Tx, Mx (not fx itself)
    const int a = axis(tokens[0].substr(1));
    const char kind = tokens[0][0];
    if (a < 0 || (name == tokens[0] && kind != 't')) return -1;
    if (kind == 'f') return a;
    if (kind == 't' || kind == 'm') return 3 + a;
    return -1;
  }
  if (tokens.size() >= 2) {  // force_x, torque_x, field.wrench.force.x, /ft/wrench/torque/z
    const int a = axis(tokens.back());
    const std::string& kind = tokens[tokens.size() - 2];
    if (a < 0) return -1;
    if (kind == "force") return a;
    if (kind == "torque" || kind == "moment") return 3 + a;
  }
  return -1;
}

ColumnGroup position_columns(const std::vector<Joint>& joints,
                             const std::vector<std::string>& header, const std::string& where) {
  ColumnGroup out;
  for (const Joint& joint : joints) {
    const BoundColumn b = joint_column(joint, header, "");
    if (b.column < 0)
      throw InputError(fmt::format(
          "{}: no column for joint '{}' (expected '{}'{})", where, joint.name, joint.name,
          joint.type == JointType::Revolute ? fmt::format(" or '{}_deg'", joint.name) : ""));
    out.push_back(b);
  }
  return out;
}

Eigen::Vector3d level_gravity_of(const Model& model, GravityFrom from, const SampleOptions& options,
                                 const std::string& where) {
  if (from == GravityFrom::Tilt) return tilt_level_gravity(model, options, where);
  if (options.level_gravity) {
    const char* source = from == GravityFrom::Columns ? "its columns gx,gy,gz"
                         : from == GravityFrom::UpstreamJoints
                             ? "the joints above the sensor link and the root gravity"
                             : "the measured force";
    throw InputError(
        fmt::format("{}: a level gravity is given, but the file has no tilt columns "
                    "tilt_x_deg,tilt_y_deg for it to turn (its gravity comes from {}): drop it",
                    where, source),
        {Hint{Hint::Setting::LevelGravity, ""}});
  }
  return Eigen::Vector3d::Zero();
}

std::vector<std::pair<std::string, double>> unlogged_joints(const Model& model,
                                                            const std::vector<std::string>& header,
                                                            const ColumnNames& names) {
  const auto has = [&](const std::string& role) { return has_role(header, names, role); };
  std::vector<std::pair<std::string, double>> out;
  for (const Joint& j : model.joints) {
    if (has(j.name) || (j.type == JointType::Revolute && has(j.name + "_deg"))) continue;
    const double reference = j.limited ? std::clamp(0.0, j.lower, j.upper) : 0.0;
    out.emplace_back(j.name, reference);
  }
  return out;
}

Model with_pose_columns(Model model, const std::vector<std::string>& header,
                        const std::string& where, const ColumnNames& names) {
  if (model.pose != SensorPoseColumns::None) return model;
  const auto has = [&](const std::string& role) { return has_role(header, names, role); };
  // Whether the header has all of a group (some of it: an error).
  const auto complete = [&](const auto& group) {
    std::vector<std::string> missing;
    for (const char* n : group)
      if (!has(n)) missing.push_back(n);
    if (!missing.empty() && missing.size() < std::size(group))
      throw InputError(fmt::format(
          "{}: column(s) {} missing (the header has some of the sensor's pose {} but not all): "
          "give all of them, or rename the columns that are not these",
          where, fmt::join(missing, ","), fmt::join(std::begin(group), std::end(group), ",")));
    return missing.empty();
  };
  const bool quaternion = complete(kPoseQuaternion), matrix = complete(kPoseMatrix);
  if (!quaternion && !matrix) return model;  // x,y,z alone: no pose, columns as before
  const bool position = complete(kPosePosition);
  const std::string pose = quaternion ? "qx,qy,qz,qw" : "r11..r33";
  if (quaternion && matrix)
    throw InputError(fmt::format(
        "{}: the header has both a quaternion qx,qy,qz,qw and a rotation matrix r11..r33 for the "
        "sensor's orientation: give one of them",
        where));
  // Other sources of what the pose gives: the columns `names` the header has,
  // named as `before` OTHERS `after`.
  const auto refuse_beside = [&](const std::vector<std::string>& names, const std::string& before,
                                 const std::string& after) {
    std::vector<std::string> others;
    for (const std::string& n : names)
      if (has(n)) others.push_back(n);
    if (!others.empty())
      throw InputError(fmt::format("{}: the sensor's pose ({}) and {}{}{}", where, pose, before,
                                   fmt::join(others, ","), after));
  };
  refuse_beside({"gx", "gy", "gz", "tilt_x_deg", "tilt_y_deg"}, "columns ",
                " both give gravity in the sensor frame: give one of them (with the pose, gravity "
                "is --root-gravity turned into the sensor frame)");
  refuse_beside({std::begin(kSensorMotion), std::end(kSensorMotion)}, "columns ",
                " both give the sensor frame's motion: give one of them (with the pose, its "
                "motion is derived from the pose)");
  std::vector<std::string> joints;
  for (const Joint& j : model.upstream_joints) {
    joints.push_back(j.name);
    joints.push_back(j.name + "_deg");
  }
  refuse_beside(joints, fmt::format("the joints above sensor link '{}' (", model.sensor_link()),
                ") both give its orientation: give one of them");
  if (matrix)
    for (const char* n : kPoseMatrix)
      for (const char* suffix : {"_vel", "_acc"})
        if (has(std::string(n) + suffix))
          throw InputError(fmt::format(
              "{}: column '{}{}': the rates of a rotation matrix are not read (the pose's rates "
              "are read for a quaternion, qx_vel..qw_vel and qx_acc..qw_acc, with x,y,z's): give "
              "the orientation as a quaternion, or no rates (derived from t)",
              where, n, suffix));
  return with_sensor_pose(std::move(model),
                          quaternion ? SensorPoseColumns::Quaternion : SensorPoseColumns::Matrix,
                          position);
}

ColumnMap map_columns(const Model& model, const std::vector<std::string>& header,
                      const std::string& where, WrenchColumns wrench, const ColumnNames& names,
                      bool sensor_motion) {
  // The role of every column: its own name, unless a binding or a spelling
  // says otherwise ("" for a column named as a role bound to another column).
  std::vector<std::string> roles = header;
  std::vector<std::string> renamed, ignored_why;
  const Hint columns_hint{Hint::Setting::Columns, ""};
  std::set<std::string> seen_roles, seen_names;
  for (const auto& [role, name] : names.bind) {
    if (!is_role(model, role)) {
      std::vector<std::string> joints;
      for (const auto* js : {&model.joints, &model.upstream_joints})
        for (const Joint& j : *js) joints.push_back(j.name);
      throw InputError(
          fmt::format("{}: '{}={}' binds an unknown role '{}': the roles are fx,fy,fz,mx,my,mz, "
                      "gx,gy,gz, t, block, wx,wy,wz,dwx,dwy,dwz,ax,ay,az, tilt_x_deg,tilt_y_deg, "
                      "qx,qy,qz,qw, r11..r33, x,y,z and the joints ({}), also as JOINT_deg, "
                      "JOINT_vel, JOINT_acc, JOINT_deg_vel, "
                      "JOINT_deg_acc",
                      where, role, name, role, name_list(joints)),
          {columns_hint});
    }
    if (!seen_roles.insert(role).second)
      throw InputError(
          fmt::format("{}: role '{}' is bound twice: bind each role to one column", where, role),
          {columns_hint});
    if (!seen_names.insert(name).second)
      throw InputError(
          fmt::format("{}: column '{}' is bound to two roles: bind each column to one role", where,
                      name),
          {columns_hint});
    const int col = find(header, name);
    if (col < 0)
      throw InputError(fmt::format("{}: no column '{}' to read as '{}': the header has {}", where,
                                   name, role, name_list(header)),
                       {columns_hint});
  }
  for (const auto& [role, name] : names.bind) {
    const int col = find(header, name);
    for (size_t c = 0; c < roles.size(); ++c)
      if (roles[c] == role && static_cast<int>(c) != col) {
        roles[c] = "";
        ignored_why.push_back(fmt::format("{} (bound to '{}' instead)", header[c], name));
      }
    roles[col] = role;
    if (name != role) renamed.push_back(fmt::format("{} as {}", name, role));
  }
  // Recorders' spellings of the wrench: each role from one column, all six or none.
  int candidate[6] = {-1, -1, -1, -1, -1, -1};
  if (names.spellings) {
    bool complete = true, spelled = false;
    for (int k = 0; k < 6; ++k) {
      if (find(roles, kWrenchColumns[k]) >= 0) continue;
      for (size_t c = 0; c < header.size(); ++c) {
        if (roles[c] != header[c] || seen_names.count(header[c]) || is_role(model, header[c]) ||
            wrench_spelling(header[c]) != k)
          continue;
        if (candidate[k] >= 0)
          throw InputError(
              fmt::format("{}: columns '{}' and '{}' could both be {} (recorders' spellings of "
                          "it): say which to read",
                          where, header[candidate[k]], header[c], kWrenchColumns[k]),
              {{Hint::Setting::Columns,
                fmt::format("{}={}", kWrenchColumns[k], header[candidate[k]])}});
        candidate[k] = static_cast<int>(c);
      }
      complete &= candidate[k] >= 0;
      spelled |= candidate[k] >= 0;
    }
    if (complete && spelled)
      for (int k = 0; k < 6; ++k)
        if (candidate[k] >= 0) {
          roles[candidate[k]] = kWrenchColumns[k];
          renamed.push_back(fmt::format("{} as {}", header[candidate[k]], kWrenchColumns[k]));
        }
  }

  ColumnMap m;
  m.q = position_columns(model.joints, roles, where);
  m.qd = suffixed(model.joints, roles, where, "_vel");
  m.qdd = suffixed(model.joints, roles, where, "_acc");
  if (m.qd.empty() != m.qdd.empty())
    throw InputError(
        fmt::format("{}: the header has joint {} columns but no {} columns: give "
                    "both, or neither (derived from t and the positions)",
                    where, m.qd.empty() ? "_acc" : "_vel", m.qd.empty() ? "_vel" : "_acc"));
  // The sensor frame's motion: all nine or none; in part, an error only where
  // it is needed (an IMU's ax,ay,az beside the wrench of a static fit).
  {
    std::vector<std::string> present, missing;
    for (const char* n : kSensorMotion) (find(roles, n) >= 0 ? present : missing).push_back(n);
    if (missing.empty()) {
      for (const char* n : kSensorMotion) m.sensor_motion.push_back({find(roles, n), 1.0});
    } else if (!present.empty()) {
      const std::string accel =
          find(roles, "ax") >= 0 || find(roles, "ay") >= 0 || find(roles, "az") >= 0
              ? "; ax,ay,az are read as the sensor frame's origin acceleration without gravity, "
                "m/s^2 (an IMU's reading in g, gravity included, is not that)"
              : "";
      if (sensor_motion)
        throw InputError(fmt::format(
            "{}: column(s) {} missing (the header has some of the sensor frame's motion "
            "wx,wy,wz,dwx,dwy,dwz,ax,ay,az but not all){}: give all nine, or rename the columns "
            "that are not these",
            where, fmt::join(missing, ","), accel));
      for (const std::string& n : present) {
        const int c = find(roles, n);
        roles[c] = "";
        ignored_why.push_back(header[c]);
      }
      ignored_why.back() +=
          fmt::format(" (the sensor frame's motion in part, without {}: a static fit needs none{})",
                      fmt::join(missing, ","), accel);
    }
  }
  // Joints above the sensor link: once one is there, all of them.
  const bool any_upstream =
      std::any_of(model.upstream_joints.begin(), model.upstream_joints.end(), [&](const Joint& j) {
        return find(roles, j.name) >= 0 || find(roles, j.name + "_deg") >= 0;
      });
  if (any_upstream) {
    m.q_upstream = position_columns(model.upstream_joints, roles, where);
    m.qd_upstream = suffixed(model.upstream_joints, roles, where, "_vel");
    m.qdd_upstream = suffixed(model.upstream_joints, roles, where, "_acc");
    if (m.qd_upstream.empty() != m.qdd_upstream.empty())
      throw InputError(
          fmt::format("{}: the upstream joints have _vel or _acc columns but not both", where));
  }
  {
    std::vector<std::string> missing;
    for (const char* n : kWrenchColumns) {
      m.wrench.push_back({find(roles, n), 1.0});
      if (m.wrench.back().column < 0) missing.push_back(n);
    }
    const Hint proposal{Hint::Setting::Columns, wrench_proposal(header, roles, candidate)};
    if (missing.size() == 6) {
      m.wrench.clear();
      if (wrench == WrenchColumns::Required)
        throw InputError(
            fmt::format("{}: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed, and "
                        "the header has {}: bind the wrench's columns to them",
                        where, name_list(header)),
            {proposal});
    } else if (!missing.empty()) {
      throw InputError(
          fmt::format("{}: column(s) {} missing (the header has some of fx,fy,fz,mx,my,mz but "
                      "not all; it has {}): bind the wrench's columns to them",
                      where, fmt::join(missing, ","), name_list(header)),
          {proposal});
    }
  }
  m.time = find(roles, "t");
  m.block = find(roles, "block");
  m.gravity = all_or_none(roles, where, {"gx", "gy", "gz"});
  m.tilt = all_or_none(roles, where, {"tilt_x_deg", "tilt_y_deg"});
  for (BoundColumn& b : m.tilt) b.scale = std::numbers::pi / 180.0;
  if (!m.gravity.empty())
    m.gravity_from = GravityFrom::Columns;
  else if (!m.q_upstream.empty() && !m.tilt.empty())
    throw InputError(fmt::format(
        "{}: tilt_x_deg,tilt_y_deg and the joints above sensor link '{}' both turn gravity: give "
        "gx,gy,gz (sensor frame) instead, or drop one",
        where, model.sensor_link()));
  else if (!m.q_upstream.empty())
    m.gravity_from = GravityFrom::UpstreamJoints;
  else if (!m.tilt.empty())
    m.gravity_from = GravityFrom::Tilt;
  else if (!m.wrench.empty())
    m.gravity_from = GravityFrom::Force;
  else
    throw InputError(
        fmt::format("{}: no gravity: add columns gx,gy,gz (m/s^2, sensor frame), or "
                    "tilt_x_deg,tilt_y_deg (the platform's tilt)",
                    where));

  // The note: what was read under another name, what was ignored and why.
  std::vector<bool> read(header.size(), false);
  for (const ColumnGroup* g : {&m.q, &m.qd, &m.qdd, &m.sensor_motion, &m.q_upstream, &m.qd_upstream,
                               &m.qdd_upstream, &m.wrench, &m.gravity, &m.tilt})
    for (const BoundColumn& b : *g) read[b.column] = true;
  for (const int c : {m.time, m.block})
    if (c >= 0) read[c] = true;
  std::vector<std::string> ignored = ignored_why;
  for (size_t c = 0; c < header.size(); ++c)
    if (!read[c] && roles[c] == header[c]) ignored.push_back(header[c]);
  m.unread.assign(ignored.begin() + static_cast<std::ptrdiff_t>(ignored_why.size()), ignored.end());
  const bool no_wrench = m.wrench.empty() && !ignored.empty();
  m.roles = roles;
  if (renamed.empty() && ignored_why.empty() && !no_wrench && model.pose == SensorPoseColumns::None)
    return m;
  if (model.pose != SensorPoseColumns::None) {  // the note says where the pose comes from
    std::vector<std::string> pose;
    for (const BoundColumn& b : m.q_upstream) pose.push_back(header[b.column]);
    renamed.push_back(fmt::format(
        "the sensor's pose from {} (world from sensor; gravity is --root-gravity turned into the "
        "sensor frame{})",
        fmt::join(pose, ","),
        pose.size() == 4 || pose.size() == 9 ? "; without x,y,z: at rest only" : ""));
  }
  std::vector<std::string> parts;
  if (!renamed.empty()) parts.push_back("read " + fmt::format("{}", fmt::join(renamed, ", ")));
  if (no_wrench)
    parts.push_back("no measured wrench (fx..mz, or a recorder's spelling of all six)");
  if (!ignored.empty()) parts.push_back("ignored: " + name_list(ignored, ", "));
  m.note = fmt::format("{}: {}", where, fmt::join(parts, "; "));
  return m;
}

}  // namespace massid::detail

namespace massid {

Eigen::Vector3d tilt_level_gravity(const Model& model, const SampleOptions& options,
                                   const std::string& where) {
  if (options.level_gravity) return *options.level_gravity;
  if (model.num_upstream_joints() > 0) {
    std::vector<std::string> names;
    for (const Joint& j : model.upstream_joints) names.push_back(j.name);
    throw InputError(
        fmt::format("{}: tilt_x_deg,tilt_y_deg turn the level gravity in the sensor frame, and "
                    "sensor link '{}' is below movable joints ({}) whose columns the file does "
                    "not have: give the level gravity in the sensor frame, or those columns",
                    where, model.sensor_link(), fmt::join(names, ", ")),
        {Hint{Hint::Setting::LevelGravity, ""}});
  }
  return fixed_sensor_gravity(model, options.root_gravity);
}

}  // namespace massid

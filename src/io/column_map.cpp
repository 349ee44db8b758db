#include "io/column_map.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <numbers>

#include "massid/core/errors.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::detail {
namespace {

int find(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
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

// NAME + suffix for every joint, or none.
ColumnGroup suffixed(const std::vector<Joint>& joints, const std::vector<std::string>& header,
                     const std::string& where, const char* suffix) {
  ColumnGroup out;
  std::vector<std::string> missing;
  for (const Joint& j : joints) {
    out.push_back({find(header, j.name + suffix), 1.0});
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

}  // namespace

ColumnGroup position_columns(const std::vector<Joint>& joints,
                             const std::vector<std::string>& header, const std::string& where) {
  ColumnGroup out;
  for (const Joint& joint : joints) {
    BoundColumn b{find(header, joint.name), 1.0};
    if (b.column < 0 && joint.type == JointType::Revolute)
      b = {find(header, joint.name + "_deg"), std::numbers::pi / 180.0};
    if (b.column < 0)
      throw InputError(fmt::format(
          "{}: no column for joint '{}' (expected '{}'{})", where, joint.name, joint.name,
          joint.type == JointType::Revolute ? fmt::format(" or '{}_deg'", joint.name) : ""));
    out.push_back(b);
  }
  return out;
}

ColumnMap map_columns(const Model& model, const std::vector<std::string>& header,
                      const std::string& where, WrenchColumns wrench) {
  ColumnMap m;
  m.q = position_columns(model.joints, header, where);
  m.qd = suffixed(model.joints, header, where, "_vel");
  m.qdd = suffixed(model.joints, header, where, "_acc");
  if (m.qd.empty() != m.qdd.empty())
    throw InputError(
        fmt::format("{}: the header has joint {} columns but no {} columns: give "
                    "both, or neither (derived from t and the positions)",
                    where, m.qd.empty() ? "_acc" : "_vel", m.qd.empty() ? "_vel" : "_acc"));
  m.sensor_motion =
      all_or_none(header, where, {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"});
  // Joints above the sensor link: once one is there, all of them.
  const bool any_upstream =
      std::any_of(model.upstream_joints.begin(), model.upstream_joints.end(), [&](const Joint& j) {
        return find(header, j.name) >= 0 || find(header, j.name + "_deg") >= 0;
      });
  if (any_upstream) {
    m.q_upstream = position_columns(model.upstream_joints, header, where);
    m.qd_upstream = suffixed(model.upstream_joints, header, where, "_vel");
    m.qdd_upstream = suffixed(model.upstream_joints, header, where, "_acc");
    if (m.qd_upstream.empty() != m.qdd_upstream.empty())
      throw InputError(
          fmt::format("{}: the upstream joints have _vel or _acc columns but not both", where));
  }
  m.wrench = all_or_none(header, where, {"fx", "fy", "fz", "mx", "my", "mz"});
  if (m.wrench.empty() && wrench == WrenchColumns::Required)
    throw InputError(
        fmt::format("{}: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed", where));
  m.time = find(header, "t");
  m.block = find(header, "block");
  m.gravity = all_or_none(header, where, {"gx", "gy", "gz"});
  m.tilt = all_or_none(header, where, {"tilt_x_deg", "tilt_y_deg"});
  for (BoundColumn& b : m.tilt) b.scale = std::numbers::pi / 180.0;
  if (!m.gravity.empty())
    m.gravity_from = GravityFrom::Columns;
  else if (!m.q_upstream.empty())
    m.gravity_from = GravityFrom::UpstreamJoints;
  else if (!m.wrench.empty())
    m.gravity_from = GravityFrom::Force;
  else
    throw InputError(
        fmt::format("{}: no gravity: add columns gx,gy,gz (m/s^2, sensor frame)", where));
  return m;
}

}  // namespace massid::detail

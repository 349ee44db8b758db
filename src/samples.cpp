#include "massid/samples.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "massid/csv.hpp"
#include "massid/errors.hpp"
#include "massid/kinematics.hpp"

namespace massid {

const char* const kWrenchColumns[6] = {"fx", "fy", "fz", "mx", "my", "mz"};

namespace {

// The columns that read_samples takes its numbers from: a CSV table (errors
// name file:line:column) or named arrays (errors name data['column'][row]).
struct TableColumns {
  const CsvTable& table;
  int rows() const { return table.num_rows(); }
  int find(const std::string& name) const { return table.find(name); }
  double number(int r, int c) const { return table.number(r, c); }
  int line(int r) const { return table.line[r]; }
  // "file:line" of the header, "file:line:column: column 'x'" of a cell.
  std::string header_where() const { return fmt::format("{}:{}", table.source, table.header_line); }
  std::string row_where(int r) const { return fmt::format("{}:{}", table.source, table.line[r]); }
  std::string cell_where(int r, int c) const {
    return fmt::format("{}:{}:{}: column '{}'", table.source, table.line[r],
                       table.column_offset[r][c], table.header[c]);
  }
};

struct ArrayColumns {
  const std::string& source;
  const std::vector<std::string>& names;
  const std::vector<Eigen::VectorXd>& values;
  int rows() const { return values.empty() ? 0 : static_cast<int>(values.front().size()); }
  int find(const std::string& name) const {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  }
  double number(int r, int c) const {
    const double v = values[c][r];
    if (!std::isfinite(v))
      throw InputError(fmt::format("{}: {} is not a finite number", cell_where(r, c), v));
    return v;
  }
  int line(int r) const { return r; }
  std::string header_where() const { return source; }
  std::string row_where(int r) const { return fmt::format("{} row {}", source, r); }
  std::string cell_where(int r, int c) const {
    return fmt::format("{}['{}'][{}]", source, names[c], r);
  }
};

// Indices of a group of columns that must be all present or all absent.
template <class Columns>
std::vector<int> column_group(const Columns& table, std::initializer_list<const char*> names) {
  std::vector<int> idx;
  std::vector<std::string> missing;
  for (const char* n : names) {
    idx.push_back(table.find(n));
    if (idx.back() < 0) missing.push_back(n);
  }
  const size_t found = std::count_if(idx.begin(), idx.end(), [](int c) { return c >= 0; });
  if (found == 0) return {};
  if (found < idx.size())
    throw InputError(fmt::format("{}: column(s) {} missing (the header has some of {} but not all)",
                                 table.header_where(), fmt::join(missing, ","),
                                 fmt::join(names.begin(), names.end(), ",")));
  return idx;
}

template <class Columns>
Eigen::MatrixXd joint_columns(const Model& model, const Columns& table) {
  const int N = table.rows();
  const int nj = model.num_joints();
  Eigen::MatrixXd q(N, nj);
  for (int j = 0; j < nj; ++j) {
    const Joint& joint = model.joints[j];
    int c = table.find(joint.name);
    double scale = 1.0;
    if (c < 0 && joint.type == JointType::Revolute) {
      c = table.find(joint.name + "_deg");
      scale = std::numbers::pi / 180.0;
    }
    if (c < 0)
      throw InputError(fmt::format(
          "{}: no column for joint '{}' (expected '{}'{})", table.header_where(), joint.name,
          joint.name,
          joint.type == JointType::Revolute ? fmt::format(" or '{}_deg'", joint.name) : ""));
    for (int r = 0; r < N; ++r) q(r, j) = scale * table.number(r, c);
  }
  return q;
}

// Columns NAME + suffix for every joint, or none: [N x joints] (0 columns when none).
template <class Columns>
Eigen::MatrixXd optional_joint_columns(const std::vector<Joint>& joints, const Columns& table,
                                       const char* suffix) {
  std::vector<int> idx;
  std::vector<std::string> missing;
  for (const Joint& j : joints) {
    idx.push_back(table.find(j.name + suffix));
    if (idx.back() < 0) missing.push_back(j.name + suffix);
  }
  if (missing.size() == joints.size()) return Eigen::MatrixXd(table.rows(), 0);
  if (!missing.empty())
    throw InputError(
        fmt::format("{}: column(s) {} missing (the header has {} columns for some "
                    "joints but not all)",
                    table.header_where(), fmt::join(missing, ","), suffix));
  Eigen::MatrixXd m(table.rows(), static_cast<Eigen::Index>(joints.size()));
  for (int r = 0; r < table.rows(); ++r)
    for (size_t j = 0; j < joints.size(); ++j) m(r, j) = table.number(r, idx[j]);
  return m;
}

// Positions of `joints` (by name, or NAME_deg), or 0 columns when none is present.
template <class Columns>
Eigen::MatrixXd optional_positions(const std::vector<Joint>& joints, const Columns& table) {
  size_t found = 0;
  for (const Joint& j : joints)
    if (table.find(j.name) >= 0 || table.find(j.name + "_deg") >= 0) ++found;
  if (found == 0) return Eigen::MatrixXd(table.rows(), 0);
  Model chain;
  chain.joints = joints;
  return joint_columns(chain, table);
}

template <class Columns>
Samples samples_of(const Model& model, const Columns& table, const std::string& source,
                   WrenchColumns wrench, const SampleOptions& options) {
  const double g0 = options.g0;
  Samples s;
  s.source = source;
  s.root_gravity = options.root_gravity;
  const int N = table.rows();
  s.line.resize(N);
  for (int r = 0; r < N; ++r) s.line[r] = table.line(r);

  s.q = joint_columns(model, table);
  // Motion: velocities and accelerations, the sensor frame's motion.
  s.qd = optional_joint_columns(model.joints, table, "_vel");
  s.qdd = optional_joint_columns(model.joints, table, "_acc");
  if (s.qd.cols() != s.qdd.cols())
    throw InputError(fmt::format(
        "{}: the header has joint {} columns but no {} columns: give "
        "both, or neither (derived from t and the positions)",
        table.header_where(), s.qd.cols() ? "_vel" : "_acc", s.qd.cols() ? "_acc" : "_vel"));
  if (model.num_joints() == 0) {
    s.qd.resize(N, 0);
    s.qdd.resize(N, 0);
  }
  if (const std::vector<int> m =
          column_group(table, {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"});
      !m.empty()) {
    s.sensor_motion.resize(N, 9);
    for (int r = 0; r < N; ++r)
      for (int k = 0; k < 9; ++k) s.sensor_motion(r, k) = table.number(r, m[k]);
  }
  // Joints above the sensor link.
  s.q_upstream = optional_positions(model.upstream_joints, table);
  if (s.q_upstream.cols() > 0) {
    s.qd_upstream = optional_joint_columns(model.upstream_joints, table, "_vel");
    s.qdd_upstream = optional_joint_columns(model.upstream_joints, table, "_acc");
    if (s.qd_upstream.cols() != s.qdd_upstream.cols())
      throw InputError(fmt::format("{}: the upstream joints have _vel or _acc columns but not both",
                                   table.header_where()));
  }

  const std::vector<int> w = column_group(table, {"fx", "fy", "fz", "mx", "my", "mz"});
  if (w.empty() && wrench == WrenchColumns::Required)
    throw InputError(fmt::format("{}: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed",
                                 table.header_where()));
  if (!w.empty()) {
    s.wrench.resize(N, 6);
    for (int r = 0; r < N; ++r)
      for (int k = 0; k < 6; ++k) s.wrench(r, k) = table.number(r, w[k]);
  }

  if (const int c = table.find("t"); c >= 0) {
    s.time.resize(N);
    for (int r = 0; r < N; ++r) s.time[r] = table.number(r, c);
  }
  if (const int c = table.find("block"); c >= 0) {
    s.block.resize(N);
    for (int r = 0; r < N; ++r) {
      const double b = table.number(r, c);
      if (b != std::round(b) || std::abs(b) > 1e9)
        throw InputError(
            fmt::format("{}: '{}' is not an integer", table.cell_where(r, c), format_number(b)));
      s.block[r] = static_cast<int>(b);
    }
  }

  const std::vector<int> g = column_group(table, {"gx", "gy", "gz"});
  s.gravity.resize(N, 3);
  if (!g.empty()) {
    for (int r = 0; r < N; ++r)
      for (int k = 0; k < 3; ++k) s.gravity(r, k) = table.number(r, g[k]);
    resolve_upstream(model, s);
  } else if (s.q_upstream.cols() > 0) {
    s.gravity_from_upstream = true;
    resolve_upstream(model, s);
  } else if (s.has_wrench()) {
    s.gravity_from_force = true;
    for (int r = 0; r < N; ++r) {
      const Eigen::Vector3d f = s.wrench.row(r).head<3>();
      if (!(f.norm() > 0.0))
        throw InputError(
            fmt::format("{}: zero force: no gx,gy,gz columns and no force to take "
                        "the gravity direction from",
                        table.row_where(r)));
      s.gravity.row(r) = g0 * f / f.norm();  // paper eq. 37
    }
  } else {
    throw InputError(fmt::format("{}: no gravity: add columns gx,gy,gz (m/s^2, sensor frame)",
                                 table.header_where()));
  }
  return s;
}

}  // namespace

void resolve_upstream(const Model& model, Samples& s) {
  if (s.q_upstream.cols() == 0 || model.num_upstream_joints() == 0) return;
  const bool moving = s.qd_upstream.cols() > 0 && s.sensor_motion.cols() == 0;
  if (!s.gravity_from_upstream && !moving) return;
  if (moving) s.sensor_motion.resize(s.size(), 9);
  const Eigen::VectorXd none(0);
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::VectorXd qu = s.q_upstream.row(i).transpose();
    const SensorPose pose = moving
                                ? upstream_kinematics(model, qu, s.qd_upstream.row(i).transpose(),
                                                      s.qdd_upstream.row(i).transpose())
                                : upstream_kinematics(model, qu, none, none);
    if (s.gravity_from_upstream)
      s.gravity.row(i) = (pose.rotation.transpose() * s.root_gravity).transpose();
    if (moving) {
      s.sensor_motion.block<1, 3>(i, 0) = pose.motion.omega.transpose();
      s.sensor_motion.block<1, 3>(i, 3) = pose.motion.omega_dot.transpose();
      s.sensor_motion.block<1, 3>(i, 6) = pose.motion.accel.transpose();
    }
  }
}

Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table) {
  return joint_columns(model, TableColumns{table});
}

Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench, double g0) {
  SampleOptions options;
  options.g0 = g0;
  return samples_of(model, TableColumns{table}, table.source, wrench, options);
}

Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench,
                     const SampleOptions& options) {
  return samples_of(model, TableColumns{table}, table.source, wrench, options);
}

Samples samples_from_columns(const Model& model, const std::vector<std::string>& names,
                             const std::vector<Eigen::VectorXd>& columns, WrenchColumns wrench,
                             const std::string& source, double g0) {
  if (names.size() != columns.size())
    throw InputError(
        fmt::format("{}: {} column names for {} columns", source, names.size(), columns.size()));
  for (size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].size() != columns.front().size())
      throw InputError(fmt::format("{}: column '{}' has {} rows, column '{}' has {}", source,
                                   names[c], columns[c].size(), names.front(),
                                   columns.front().size()));
    if (std::count(names.begin(), names.end(), names[c]) > 1)
      throw InputError(fmt::format("{}: column '{}' appears twice", source, names[c]));
  }
  SampleOptions options;
  options.g0 = g0;
  return samples_of(model, ArrayColumns{source, names, columns}, source, wrench, options);
}

}  // namespace massid

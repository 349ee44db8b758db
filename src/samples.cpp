#include "massid/samples.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "massid/errors.hpp"

namespace massid {

const char* const kWrenchColumns[6] = {"fx", "fy", "fz", "mx", "my", "mz"};

namespace {

// Indices of a group of columns that must be all present or all absent.
std::vector<int> column_group(const CsvTable& table, std::initializer_list<const char*> names) {
  std::vector<int> idx;
  std::vector<std::string> missing;
  for (const char* n : names) {
    idx.push_back(table.find(n));
    if (idx.back() < 0) missing.push_back(n);
  }
  const size_t found = std::count_if(idx.begin(), idx.end(), [](int c) { return c >= 0; });
  if (found == 0) return {};
  if (found < idx.size())
    throw InputError(fmt::format(
        "{}:{}: column(s) {} missing (the header has some of {} but not all)", table.source,
        table.header_line, fmt::join(missing, ","), fmt::join(names.begin(), names.end(), ",")));
  return idx;
}

}  // namespace

Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table) {
  const int N = table.num_rows();
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
          "{}:{}: no column for joint '{}' (expected '{}'{})", table.source, table.header_line,
          joint.name, joint.name,
          joint.type == JointType::Revolute ? fmt::format(" or '{}_deg'", joint.name) : ""));
    for (int r = 0; r < N; ++r) q(r, j) = scale * table.number(r, c);
  }
  return q;
}

Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench, double g0) {
  Samples s;
  s.source = table.source;
  const int N = table.num_rows();
  s.line = table.line;

  s.q = read_joint_columns(model, table);

  const std::vector<int> w = column_group(table, {"fx", "fy", "fz", "mx", "my", "mz"});
  if (w.empty() && wrench == WrenchColumns::Required)
    throw InputError(
        fmt::format("{}:{}: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed",
                    table.source, table.header_line));
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
        throw InputError(fmt::format("{}:{}:{}: column 'block': '{}' is not an integer",
                                     table.source, table.line[r], table.column_offset[r][c],
                                     table.rows[r][c]));
      s.block[r] = static_cast<int>(b);
    }
  }

  const std::vector<int> g = column_group(table, {"gx", "gy", "gz"});
  s.gravity.resize(N, 3);
  if (!g.empty()) {
    for (int r = 0; r < N; ++r)
      for (int k = 0; k < 3; ++k) s.gravity(r, k) = table.number(r, g[k]);
  } else if (s.has_wrench()) {
    s.gravity_from_force = true;
    for (int r = 0; r < N; ++r) {
      const Eigen::Vector3d f = s.wrench.row(r).head<3>();
      if (!(f.norm() > 0.0))
        throw InputError(
            fmt::format("{}:{}: zero force: no gx,gy,gz columns and no force to take "
                        "the gravity direction from",
                        table.source, table.line[r]));
      s.gravity.row(r) = g0 * f / f.norm();  // paper eq. 37
    }
  } else {
    throw InputError(fmt::format("{}:{}: no gravity: add columns gx,gy,gz (m/s^2, sensor frame)",
                                 table.source, table.header_line));
  }
  return s;
}

}  // namespace massid

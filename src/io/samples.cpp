#include "massid/core/samples.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "core/argument_checks.hpp"
#include "io/column_map.hpp"
#include "io/csv_stream.hpp"
#include "io/edit_distance.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/gravity.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

const char* const kWrenchColumns[6] = {"fx", "fy", "fz", "mx", "my", "mz"};

namespace {

// The columns that read_samples takes its numbers from: a CSV table (errors
// name file:line:column) or named arrays (errors name data['column'][row]).
struct TableColumns {
  const CsvTable& table;
  int rows() const { return table.num_rows(); }
  const std::vector<std::string>& names() const { return table.header; }
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
  const std::vector<std::string>& header;
  const std::vector<Eigen::VectorXd>& values;
  int rows() const { return values.empty() ? 0 : static_cast<int>(values.front().size()); }
  const std::vector<std::string>& names() const { return header; }
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
    return fmt::format("{}['{}'][{}]", source, header[c], r);
  }
};

// [N x group size] of a group's columns, scaled (0 columns for an absent group).
// Positions are read column by column, every other group row by row (which
// decides the cell an error names when several are bad).
enum class Order { ByColumn, ByRow };
template <class Columns>
Eigen::MatrixXd read_group(const Columns& table, const detail::ColumnGroup& group, Order order) {
  const int N = table.rows();
  const int n = static_cast<int>(group.size());
  Eigen::MatrixXd m(N, n);
  const auto cell = [&](int r, int k) {
    const detail::BoundColumn& b = group[k];
    m(r, k) = b.scale * table.number(r, b.column);
  };
  if (order == Order::ByColumn) {
    for (int k = 0; k < n; ++k)
      for (int r = 0; r < N; ++r) cell(r, k);
  } else {
    for (int r = 0; r < N; ++r)
      for (int k = 0; k < n; ++k) cell(r, k);
  }
  return m;
}

template <class Columns>
Samples samples_of(const Model& model, const Columns& table, const std::string& source,
                   WrenchColumns wrench, const SampleOptions& options) {
  const detail::ColumnMap map = detail::map_columns(model, table.names(), table.header_where(),
                                                    wrench, options.columns, options.sensor_motion);
  const Eigen::Vector3d level =
      detail::level_gravity_of(model, map.gravity_from, options, table.header_where());
  Samples s;
  s.source = source;
  s.root_gravity = options.root_gravity;
  const int N = table.rows();
  s.line.resize(N);
  for (int r = 0; r < N; ++r) s.line[r] = table.line(r);

  s.q = read_group(table, map.q, Order::ByColumn);
  s.qd = read_group(table, map.qd, Order::ByRow);
  s.qdd = read_group(table, map.qdd, Order::ByRow);
  if (!map.sensor_motion.empty())
    s.sensor_motion = read_group(table, map.sensor_motion, Order::ByRow);
  s.q_upstream = read_group(table, map.q_upstream, Order::ByColumn);
  if (!map.q_upstream.empty()) {
    s.qd_upstream = read_group(table, map.qd_upstream, Order::ByRow);
    s.qdd_upstream = read_group(table, map.qdd_upstream, Order::ByRow);
  }
  if (!map.q_upstream.empty() && model.pose != SensorPoseColumns::None) {
    // The sensor's pose: checked, normalised, a quaternion's sign continuous
    // (with its given rates); a row per column, each contiguous.
    const bool rates = s.qd_upstream.cols() > 0;
    const int nu = static_cast<int>(s.q_upstream.cols());
    Eigen::MatrixXd qu = s.q_upstream.transpose(), qdu = s.qd_upstream.transpose(),
                    qddu = s.qdd_upstream.transpose();
    for (int r = 0; r < N; ++r) {
      const std::string why = normalise_pose(model.pose, nu, qu.col(r).data());
      if (!why.empty()) throw InputError(fmt::format("{}: {}", table.row_where(r), why));
      if (r > 0)
        continue_pose_sign(model.pose, qu.col(r - 1).data(), qu.col(r).data(),
                           rates ? qdu.col(r).data() : nullptr,
                           rates ? qddu.col(r).data() : nullptr);
    }
    s.q_upstream = qu.transpose();
    s.qd_upstream = qdu.transpose();
    s.qdd_upstream = qddu.transpose();
  }
  if (!map.wrench.empty()) s.wrench = read_group(table, map.wrench, Order::ByRow);
  if (map.time >= 0) s.time = read_group(table, {{map.time, 1.0}}, Order::ByRow).col(0);
  if (map.block >= 0) {
    s.block.resize(N);
    for (int r = 0; r < N; ++r) {
      const double b = table.number(r, map.block);
      if (!detail::is_block_number(b))
        throw InputError(fmt::format("{}: '{}' is not an integer", table.cell_where(r, map.block),
                                     format_number(b)));
      s.block[r] = static_cast<int>(b);
    }
  }

  switch (map.gravity_from) {
    case detail::GravityFrom::Columns:
      s.gravity = read_group(table, map.gravity, Order::ByRow);
      resolve_upstream(model, s);
      break;
    case detail::GravityFrom::UpstreamJoints:
      s.gravity.resize(N, 3);
      s.gravity_from_upstream = true;
      resolve_upstream(model, s);
      break;
    case detail::GravityFrom::Tilt:
      s.gravity.resize(N, 3);
      for (int r = 0; r < N; ++r)
        s.gravity.row(r) =
            tilted_gravity(level, Tilt{map.tilt[0].scale * table.number(r, map.tilt[0].column),
                                       map.tilt[1].scale * table.number(r, map.tilt[1].column)})
                .transpose();
      resolve_upstream(model, s);
      break;
    case detail::GravityFrom::Force:
      s.gravity.resize(N, 3);
      s.gravity_from_force = true;
      for (int r = 0; r < N; ++r) {
        const Eigen::Vector3d f = s.wrench.row(r).head<3>();
        if (!(f.norm() > 0.0)) detail::throw_zero_force(table.row_where(r));
        s.gravity.row(r) = options.g0 * f / f.norm();  // paper eq. 37
      }
      break;
  }
  return s;
}

}  // namespace

void resolve_upstream(const Model& model, Samples& s) {
  if (s.q_upstream.cols() == 0 || model.num_upstream_joints() == 0) return;
  const bool moving = s.qd_upstream.cols() > 0 && s.sensor_motion.cols() == 0;
  if (!s.gravity_from_upstream && !moving) return;
  const int nu = model.num_upstream_joints();
  detail::check_size("resolve_upstream", "q_upstream", s.q_upstream.cols(), nu,
                     "the joints above the sensor");
  if (moving) s.sensor_motion.resize(s.size(), 9);
  // A row per column, each contiguous.
  const Eigen::MatrixXd qu = s.q_upstream.transpose(), qdu = s.qd_upstream.transpose(),
                        qddu = s.qdd_upstream.transpose();
  Eigen::Vector3d g;
  Eigen::Matrix<double, 9, 1> motion;
  for (int i = 0; i < s.size(); ++i) {
    upstream_sensor_frame(model, qu.col(i).data(), moving ? qdu.col(i).data() : nullptr,
                          moving ? qddu.col(i).data() : nullptr, s.root_gravity,
                          s.gravity_from_upstream ? g.data() : nullptr,
                          moving ? motion.data() : nullptr);
    if (s.gravity_from_upstream) s.gravity.row(i) = g.transpose();
    if (moving) s.sensor_motion.row(i) = motion.transpose();
  }
}

std::string column_note(const Model& model, const std::vector<std::string>& header,
                        const std::string& where, WrenchColumns wrench,
                        const SampleOptions& options) {
  return detail::map_columns(model, header, where, wrench, options.columns, options.sensor_motion)
      .note;
}

std::vector<std::string> column_roles(const Model& model, const std::vector<std::string>& header,
                                      const SampleOptions& options) {
  return detail::map_columns(model, header, "header", WrenchColumns::Optional, options.columns,
                             false)
      .roles;
}

std::string file_column_note(const Model& model, const std::string& path,
                             const SampleOptions& options) {
  const detail::MappedFile file(path);
  detail::SampleColumns header;
  detail::read_header(file.text(), path, header);
  return detail::bind_header(model, std::move(header), options, options.sensor_motion).note;
}

Model with_pose_columns(Model model, const std::vector<std::string>& header,
                        const std::string& where, const SampleOptions& options) {
  return detail::with_pose_columns(std::move(model), header, where, options.columns);
}

Model hold_unlogged_joints(Model model, const std::vector<std::string>& header,
                           const std::string& where, const SampleOptions& options,
                           std::optional<Warning>* note) {
  if (note) note->reset();
  model = detail::with_pose_columns(std::move(model), header, where, options.columns);
  const auto unlogged = detail::unlogged_joints(model, header, options.columns);
  if (unlogged.empty()) return model;
  model = hold_joints(std::move(model), unlogged);
  if (!note) return model;
  // Columns not read that look like a joint's: "joint" in the name, or
  // within a few edits of a held joint's name (a suffix _deg/_vel/_acc aside).
  std::vector<std::string> lookalikes;
  const auto lower = [](std::string s) {
    for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
  };
  for (const std::string& name :
       detail::map_columns(model, header, where, WrenchColumns::Optional, options.columns, false)
           .unread) {
    std::string stem = name;
    for (const char* suffix : {"_deg", "_vel", "_acc"})
      if (stem.size() > 4 && stem.ends_with(suffix)) stem.resize(stem.size() - 4);
    const bool close = std::any_of(unlogged.begin(), unlogged.end(), [&](const auto& held) {
      return detail::edit_distance(stem, held.first) <= std::max<size_t>(2, held.first.size() / 8);
    });
    if (close || lower(name).find("joint") != std::string::npos) lookalikes.push_back(name);
  }
  std::string names, positions;
  constexpr size_t kShown = 8;
  for (size_t i = 0; i < std::min(unlogged.size(), kShown); ++i)
    names += fmt::format("{}{}", i ? ", " : "", unlogged[i].first);
  if (unlogged.size() > kShown) names += fmt::format(" and {} more", unlogged.size() - kShown);
  const bool all_zero = std::all_of(unlogged.begin(), unlogged.end(),
                                    [](const auto& held) { return held.second == 0.0; });
  std::string message = fmt::format(
      "{}: {} joint{} below the sensor link '{}' {} no column and {} held still at {} ({}): "
      "everything below the sensor is one rigid body while they do not move; to hold them "
      "elsewhere, or to leave them free, give their positions or their columns",
      where, unlogged.size(), unlogged.size() == 1 ? "" : "s", model.sensor_link(),
      unlogged.size() == 1 ? "has" : "have", unlogged.size() == 1 ? "is" : "are",
      all_zero ? "0" : "the URDF's reference position (0, or the limit nearest to 0)", names);
  if (!lookalikes.empty())
    message += fmt::format(
        "; columns not read that look like joints: {} (a misspelled joint "
        "name? bind it to its joint)",
        fmt::join(lookalikes, ", "));
  *note = Warning{std::move(message),
                  {{Hint::Setting::HoldJoints, ""}, {Hint::Setting::Columns, "JOINT=NAME"}}};
  return model;
}

Model hold_unlogged_file_joints(Model model, const std::string& path, const SampleOptions& options,
                                std::optional<Warning>* note) {
  const detail::MappedFile file(path);
  detail::SampleColumns c;
  detail::read_header(file.text(), path, c);
  return hold_unlogged_joints(std::move(model), c.header, fmt::format("{}:{}", path, c.header_line),
                              options, note);
}

Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table) {
  const TableColumns columns{table};
  return read_group(columns,
                    detail::position_columns(model.joints, table.header, columns.header_where()),
                    Order::ByColumn);
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
                             const std::string& source, const SampleOptions& options) {
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
  return samples_of(model, ArrayColumns{source, names, columns}, source, wrench, options);
}

}  // namespace massid

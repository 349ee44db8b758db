#include "convert.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include "massid/core/errors.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"

namespace massid::python {

Eigen::MatrixXd to_matrix(const py::handle& array, int cols, const std::string& what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  } catch (const py::error_already_set&) {
  }
  if (!a) throw InputError(fmt::format("{}: not an array of numbers", what));
  const auto shape = [&] {
    std::vector<py::ssize_t> s(a.shape(), a.shape() + a.ndim());
    return fmt::format("({})", fmt::join(s, ", "));
  };
  if (a.ndim() == 1 && a.shape(0) == cols) {
    Eigen::MatrixXd m(1, cols);
    for (int c = 0; c < cols; ++c) m(0, c) = a.at(c);
    return m;
  }
  if (a.ndim() != 2 || a.shape(1) != cols)
    throw InputError(
        fmt::format("{}: expected shape (N, {}) or ({},), got {}", what, cols, cols, shape()));
  const Eigen::Index N = a.shape(0);
  Eigen::MatrixXd m =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          a.data(), N, cols);
  for (Eigen::Index i = 0; i < N; ++i)
    for (int c = 0; c < cols; ++c)
      if (!std::isfinite(m(i, c)))
        throw InputError(
            fmt::format("{}: element [{}, {}] is {}, not a finite number", what, i, c, m(i, c)));
  return m;
}

Eigen::VectorXd to_vector(const py::handle& array, const std::string& what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  } catch (const py::error_already_set&) {
  }
  if (!a) throw InputError(fmt::format("{}: not an array of numbers", what));
  if (a.ndim() != 1)
    throw InputError(fmt::format("{}: expected a 1-D array, got {} dimensions", what, a.ndim()));
  Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw InputError(fmt::format("{}: element [{}] is {}, not a finite number", what, i, v[i]));
  return v;
}

bool is_path(const py::handle& obj) {
  return py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__");
}

std::string path_of(const py::handle& obj) {
  return py::str(py::module_::import("os").attr("fspath")(obj));
}

std::vector<std::pair<std::string, double>> held_list(const std::map<std::string, double>& m) {
  return {m.begin(), m.end()};
}

std::map<std::string, double> held_dict(const std::vector<std::pair<std::string, double>>& held) {
  return {held.begin(), held.end()};
}

Model model_of(const py::handle& robot, const std::optional<std::string>& sensor,
               const std::optional<std::map<std::string, double>>& fixed) {
  const auto held = fixed ? held_list(*fixed) : std::vector<std::pair<std::string, double>>{};
  if (py::isinstance<Model>(robot)) {
    if (sensor)
      throw InputError(
          "sensor= goes with a URDF path; a Model already has its sensor link "
          "(load_model(urdf, sensor=...))");
    return hold_joints(robot.cast<Model>(), held);
  }
  if (!is_path(robot))
    throw InputError(fmt::format("robot: expected a URDF path or a massid.Model, got {}",
                                 std::string(py::str(py::type::of(robot).attr("__name__")))));
  return hold_joints(load_urdf(path_of(robot), sensor.value_or("")), held);
}

Columns columns_of(const py::handle& mapping) {
  if (!py::hasattr(mapping, "keys"))
    throw InputError("data: expected a CSV path or columns by name (a dict of arrays), got " +
                     std::string(py::str(py::type::of(mapping).attr("__name__"))));
  Columns out;
  for (const py::handle key : mapping.attr("keys")()) {
    const std::string name = py::str(key);
    const py::object column = mapping[key];
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
      a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(column);
    } catch (const py::error_already_set&) {
    }
    if (!a || a.ndim() != 1)
      throw InputError(fmt::format("data['{}']: expected a 1-D array of numbers", name));
    out.names.push_back(name);
    out.values.emplace_back(Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0)));
  }
  return out;
}

Samples samples_of(const Model& model, const py::handle& data, WrenchColumns wrench,
                   std::vector<std::string>* header, const SampleOptions& options,
                   CsvTable* table_out) {
  if (is_path(data)) {
    CsvTable table = read_csv(path_of(data));
    if (header) *header = table.header;
    Samples s = read_samples(model, table, wrench, options);
    if (table_out) *table_out = std::move(table);
    return s;
  }
  const Columns c = columns_of(data);
  if (header) *header = c.names;
  return samples_from_columns(model, c.names, c.values, wrench, "data", options);
}

namespace {

// Three finite numbers gx, gy, gz of the keyword `name`.
Eigen::Vector3d gravity_vector_of(const std::vector<double>& g, const char* name) {
  if (g.size() != 3) throw InputError(fmt::format("{}: three numbers gx, gy, gz", name));
  for (double v : g)
    if (!std::isfinite(v)) throw InputError(fmt::format("{}: {} is not a finite number", name, v));
  return Eigen::Map<const Eigen::Vector3d>(g.data());
}

}  // namespace

Eigen::Vector3d root_gravity_of(const std::optional<std::vector<double>>& root_gravity) {
  if (!root_gravity) return SampleOptions{}.root_gravity;
  return gravity_vector_of(*root_gravity, "root_gravity");
}

std::optional<Eigen::Vector3d> level_gravity_of(
    const std::optional<std::vector<double>>& level_gravity) {
  if (!level_gravity) return std::nullopt;
  return gravity_vector_of(*level_gravity, "level_gravity");
}

ColumnNames column_names_of(const std::optional<std::map<std::string, std::string>>& columns) {
  ColumnNames out;
  if (columns)
    for (const auto& [role, name] : *columns) out.bind.emplace_back(role, name);
  return out;
}

void warn_note(const std::string& note) {
  if (note.empty()) return;
  py::module_::import("warnings")
      .attr("warn")(note, py::module_::import("massid").attr("MassidWarning"), 3);
}

Eigen::MatrixXd optional_matrix(const py::handle& array, Eigen::Index rows, int cols,
                                const std::string& what) {
  if (array.is_none()) return Eigen::MatrixXd(0, 0);
  Eigen::MatrixXd m = to_matrix(array, cols, what);
  if (m.rows() != rows)
    throw InputError(
        fmt::format("{} has {} rows and q {}: one of each per sample", what, m.rows(), rows));
  return m;
}

py::dict csv_columns(const CsvTable& table) {
  py::dict out;
  for (int c = 0; c < table.num_columns(); ++c) {
    py::array_t<double> a(table.num_rows());
    double* p = a.mutable_data();
    for (int r = 0; r < table.num_rows(); ++r) p[r] = table.number(r, c);
    out[py::str(table.header[c])] = a;
  }
  return out;
}

}  // namespace massid::python

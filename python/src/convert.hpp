// Conversions between Python arguments and massid's types, shared by the
// bindings: arrays (numpy, any array-like) to Eigen with checked shapes
// (results go back through pybind11's Eigen casters), a robot argument
// (URDF path or Model), a data argument (CSV path or columns by name).
// Errors are massid::InputError, which Python sees as massid.InputError.
#pragma once

#include <pybind11/eigen.h>  // Eigen results return as new numpy arrays
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::python {

namespace py = pybind11;

// [N x cols] from an array-like of shape (N, cols), or (cols,) as one row.
// `what` names the argument and its columns in errors: "q (joints j1, j2)".
Eigen::MatrixXd to_matrix(const py::handle& array, int cols, const std::string& what);
// [N] from a 1-D array-like (finite numbers).
Eigen::VectorXd to_vector(const py::handle& array, const std::string& what);
// os.fspath(obj) for str and os.PathLike.
std::string path_of(const py::handle& obj);
bool is_path(const py::handle& obj);

// The model of a `robot` argument: a Model (sensor must be unset) or a URDF
// path; `fixed` joints are then held (hold_joints).
Model model_of(const py::handle& robot, const std::optional<std::string>& sensor,
               const std::optional<std::map<std::string, double>>& fixed);

std::vector<std::pair<std::string, double>> held_list(const std::map<std::string, double>& m);
std::map<std::string, double> held_dict(const std::vector<std::pair<std::string, double>>& held);

// A data argument that is not a path: columns by name (dict, or anything with
// keys() and [], a pandas DataFrame included), each a 1-D array of length N.
struct Columns {
  std::vector<std::string> names;
  std::vector<Eigen::VectorXd> values;
};
Columns columns_of(const py::handle& mapping);

// Samples of a data argument (path: read_csv and read_samples' rules).
// `header` receives the column names (for the set-up checks); `options` the
// root gravity for a sensor below movable joints (default: SampleOptions{});
// `table` (a path only) the CSV as read.
Samples samples_of(const Model& model, const py::handle& data, WrenchColumns wrench,
                   std::vector<std::string>* header = nullptr, const SampleOptions& options = {},
                   CsvTable* table = nullptr);

// A root_gravity argument: three numbers gx, gy, gz (default 0, 0, -9.80665).
Eigen::Vector3d root_gravity_of(const std::optional<std::vector<double>>& root_gravity);
// A level_gravity argument (sensor frame, what tilt columns turn:
// SampleOptions::level_gravity): three numbers gx, gy, gz; None: unset.
std::optional<Eigen::Vector3d> level_gravity_of(
    const std::optional<std::vector<double>>& level_gravity);
// The columns= keyword ({ROLE: NAME}) as read_samples' ColumnNames.
ColumnNames column_names_of(const std::optional<std::map<std::string, std::string>>& columns);
// A column note (column_note, read_samples.hpp) as a MassidWarning, when there is one.
void warn_note(const std::string& note);

// [N x cols] of an optional array argument with N rows (0 x 0 when None).
Eigen::MatrixXd optional_matrix(const py::handle& array, Eigen::Index rows, int cols,
                                const std::string& what);

// A CSV's numeric columns, by name.
py::dict csv_columns(const CsvTable& table);

}  // namespace massid::python

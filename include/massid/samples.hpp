// Samples: the numeric content of a plan or data file, bound to a model.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/csv.hpp"
#include "massid/model.hpp"

namespace massid {

constexpr double kStandardGravity = 9.80665;  // m/s^2

struct Samples {
  std::string source;
  Eigen::MatrixXd q;        // [N x num_joints] joint positions, rad or m (Model::joints order)
  Eigen::MatrixXd gravity;  // [N x 3] gravity acceleration in the sensor frame, m/s^2
  Eigen::MatrixXd wrench;   // [N x 6] fx fy fz mx my mz; 0 columns when absent
  std::vector<int> line;    // [N] file line of each sample
  Eigen::VectorXd time;     // [N] column t, s (0 rows when absent)
  std::vector<int> block;   // [N] column block: sensor re-zeroed between blocks (empty when absent)
  bool gravity_from_force = false;  // gravity taken from the force direction (eq. 37)

  int size() const { return static_cast<int>(q.rows()); }
  bool has_wrench() const { return wrench.cols() == 6; }
};

enum class WrenchColumns { Required, Optional };

// Reads joint columns (named as the joint, or JOINT_deg in degrees), gx,gy,gz,
// the wrench, and the optional t and block (integer) columns. Without gx,gy,gz, gravity is g0 times
// the unit measured force (paper eq. 37). Throws InputError naming file, line and column.
Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench,
                     double g0 = kStandardGravity);

// read_samples for columns already in memory (the Python module's dict of
// arrays): names[c] labels columns[c], all of one length. Errors name
// source['column'][row].
Samples samples_from_columns(const Model& model, const std::vector<std::string>& names,
                             const std::vector<Eigen::VectorXd>& columns, WrenchColumns wrench,
                             const std::string& source = "data", double g0 = kStandardGravity);

// [N x num_joints] joint columns (named as the joint, or JOINT_deg in degrees).
Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table);

extern const char* const kWrenchColumns[6];  // "fx" ... "mz"

}  // namespace massid

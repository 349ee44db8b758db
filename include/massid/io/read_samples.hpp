// Reading samples from a table of columns (a CSV file or arrays by name):
// which columns mean what, and the gravity and sensor motion they imply.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/csv.hpp"

namespace massid {

enum class WrenchColumns { Required, Optional };

// What a reader takes from a file beyond its columns.
struct SampleOptions {
  double g0 = kStandardGravity;  // |g| for gravity from the force direction (eq. 37)
  // Gravity in the URDF root frame, for a sensor below movable joints whose
  // columns the file has (used when the file has no gx,gy,gz).
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
};

// The columns of a data file and what each means: src/io/column_map.hpp (the one
// binding, shared with the streaming readers), listed for users in
// docs/formats.md. In short: the joints (named as the joint, or JOINT_deg in
// degrees), optionally JOINT_vel and JOINT_acc, the sensor motion wx..wz,
// dwx..dwz, ax..az, the joints above the sensor link (Model::upstream_joints)
// with their _vel/_acc, the wrench fx..mz, gravity gx,gy,gz, time t and an
// integer block. Without gx,gy,gz, gravity is root_gravity turned into the
// sensor frame by the upstream joints (gravity_from_upstream), else g0 times
// the unit measured force (paper eq. 37); with the upstream joints'
// velocities, the sensor motion follows from them too (unless the file gives
// the sensor motion itself: wx..az columns win). Throws InputError naming
// file, line and column.
Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench,
                     double g0 = kStandardGravity);
Samples read_samples(const Model& model, const CsvTable& table, WrenchColumns wrench,
                     const SampleOptions& options);

// read_samples for columns already in memory (the Python module's dict of
// arrays): names[c] labels columns[c], all of one length. Errors name
// source['column'][row].
Samples samples_from_columns(const Model& model, const std::vector<std::string>& names,
                             const std::vector<Eigen::VectorXd>& columns, WrenchColumns wrench,
                             const std::string& source = "data", const SampleOptions& options = {});

// Gravity and sensor motion from the upstream joints (as read_samples does;
// again after their derivatives were filtered or derived).
void resolve_upstream(const Model& model, Samples& samples);

// [N x num_joints] joint columns (named as the joint, or JOINT_deg in degrees).
Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table);

extern const char* const kWrenchColumns[6];  // "fx" ... "mz"

}  // namespace massid

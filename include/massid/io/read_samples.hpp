// Reading samples from a table of columns (a CSV file or arrays by name):
// which columns mean what, and the gravity and sensor motion they imply.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/csv.hpp"

namespace massid {

enum class WrenchColumns { Required, Optional };

// Columns named otherwise than their roles (docs/formats.md, "Columns named
// otherwise"). `bind`: (ROLE, NAME) pairs, each reading the column NAME as
// ROLE: fx..mz, gx..gz, t, block, wx..az, dwx..dwz, tilt_x_deg, tilt_y_deg, a
// joint (Model::joints or upstream_joints) or JOINT_deg, JOINT_vel,
// JOINT_acc. A column already named ROLE is then ignored. InputError for an
// unknown role, a name the header does not have, a role or a name given twice.
// `spellings`: where fx..mz are absent, recorders' common spellings are
// read as them (the one table: column_map.cpp): Fx/FX, tx/Tx/Mx (torque),
// force_x/torque_x, and ROS exports ending in force.x / torque.x or
// force/x / torque/x after any prefix (field.wrench.force.x,
// /ft_sensor/wrench/force/x, wrench.torque.z), only when all six come
// together and each from one column (two candidates for one: InputError
// naming both).
struct ColumnNames {
  std::vector<std::pair<std::string, std::string>> bind;
  bool spellings = true;
};

// What a reader takes from a file beyond its columns.
struct SampleOptions {
  double g0 = kStandardGravity;  // |g| for gravity from the force direction (eq. 37)
  // Gravity in the URDF root frame, for a sensor below movable joints whose
  // columns the file has (used when the file has no gx,gy,gz).
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
  // Gravity in the sensor frame with the platform level: what the tilt
  // columns tilt_x_deg,tilt_y_deg turn (a file without gx,gy,gz and without
  // the joints above the sensor link). Unset: root_gravity turned into the
  // sensor frame through the fixed joints above the sensor link
  // (tilt_level_gravity). Given for a file whose gravity comes from elsewhere:
  // InputError (it would go unused).
  std::optional<Eigen::Vector3d> level_gravity;
  // Columns bound to roles by other names.
  ColumnNames columns;
  // The reader's use needs the sensor frame's motion (a motion log): the
  // group wx..az given in part is an error. false (a static fit, a plan):
  // such a part (an IMU's ax,ay,az beside the wrench) is ignored, and
  // column_note says so.
  bool sensor_motion = true;
};

// The level gravity (sensor frame) that a file's tilt columns turn, the one
// rule of every reader and the compensator: options.level_gravity, else
// options.root_gravity turned into the sensor frame by the fixed joints above
// the sensor link (fixed_sensor_gravity, kinematics.hpp). InputError starting
// with `where` when it is unset and the sensor link is below movable joints
// (the file then lacks their columns: the sensor frame's orientation is
// unknown).
Eigen::Vector3d tilt_level_gravity(const Model& model, const SampleOptions& options,
                                   const std::string& where);

// The columns of a data file and what each means: src/io/column_map.hpp (the one
// binding, shared with the streaming readers), listed for users in
// docs/formats.md. In short: the joints (named as the joint, or JOINT_deg in
// degrees), optionally JOINT_vel and JOINT_acc, the sensor motion wx..wz,
// dwx..dwz, ax..az, the joints above the sensor link (Model::upstream_joints)
// with their _vel/_acc, the wrench fx..mz, gravity gx,gy,gz, time t and an
// integer block. Without gx,gy,gz, gravity is root_gravity turned into the
// sensor frame by the upstream joints (gravity_from_upstream), else the level
// gravity (tilt_level_gravity) turned by tilt_x_deg,tilt_y_deg, else g0 times
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

// What the binding of `header` to the model's roles did beyond the columns'
// own names, for the note every command prints (one line, without a prefix,
// starting with `where`): the columns read as a role under another name
// (ColumnNames), the groups ignored and why, and then every column not read;
// "" when every column read is read under its own name and no group was
// ignored. With WrenchColumns::Optional and no wrench bound, a header with
// columns not read gets a note too (a wrench under names not recognised
// would otherwise be silently absent). InputError as read_samples.
std::string column_note(const Model& model, const std::vector<std::string>& header,
                        const std::string& where, WrenchColumns wrench,
                        const SampleOptions& options);
// The same for a data file's header (read alone; the wrench required).
std::string file_column_note(const Model& model, const std::string& path,
                             const SampleOptions& options);

// The header as the roles its columns are read as (ColumnNames applied; ""
// for a column a binding displaced or a group ignored): what the set-up checks
// (setup_checks.hpp) take as the header. For a header read_samples accepted
// with these options.
std::vector<std::string> column_roles(const Model& model, const std::vector<std::string>& header,
                                      const SampleOptions& options);

// The model a log's header asks for when it gives the sensor's pose in the
// world frame instead of the joints above the sensor link (interface.md, "The
// sensor's pose instead of joints"): qx,qy,qz,qw or r11..r33, optionally
// x,y,z (under their names or bound by options.columns) become the model's
// upstream joints (with_sensor_pose, model.hpp), read, filtered and turned
// into gravity and the sensor frame's motion as those joints are. The model
// as it is without them. InputError starting with `where` for a pose given in
// part, as a quaternion and a matrix at once, or beside gx,gy,gz, the tilt,
// wx..az or the joints above the sensor link. Every door that reads a log
// calls it (hold_unlogged_joints does) before binding the header.
Model with_pose_columns(Model model, const std::vector<std::string>& header,
                        const std::string& where, const SampleOptions& options);

// The joints below the sensor link that a log has no column for (not under
// its name, as JOINT_deg, nor bound by options.columns), held still at their
// URDF reference position: 0, or the limit nearest to 0 when 0 is outside the
// limits (hold_joints; Model::held records them, so a params file does too).
// For a fit, everything below the sensor is one rigid body while they do not
// move, so a hand's unlogged finger joints need no column. Joints the log has
// stay free; a joint above the sensor link without its column is read_samples'
// error as before. `note` (when not null): set when any joint was held, saying
// how many, which, how to set them otherwise (the hints: hold them at other
// values, or give their columns) and the columns not read that look like
// joint columns (a misspelled joint would otherwise be held silently); unset
// when none was held. `header` as read_samples takes it; `where` starts the
// note. The sensor's pose columns are bound first (with_pose_columns).
Model hold_unlogged_joints(Model model, const std::vector<std::string>& header,
                           const std::string& where, const SampleOptions& options,
                           std::optional<Warning>* note = nullptr);
// The same for a data file's header (read alone).
Model hold_unlogged_file_joints(Model model, const std::string& path, const SampleOptions& options,
                                std::optional<Warning>* note = nullptr);

// [N x num_joints] joint columns (named as the joint, or JOINT_deg in degrees).
Eigen::MatrixXd read_joint_columns(const Model& model, const CsvTable& table);

extern const char* const kWrenchColumns[6];  // "fx" ... "mz"

}  // namespace massid

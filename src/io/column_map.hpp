// The one binding of a data file's header to the roles of its columns, for
// every reader: read_samples (a CSV table), samples_from_columns (the Python
// module's named arrays) and the memory-mapped streaming readers
// (csv_stream.hpp). Every header error is raised here, once.
//
// The roles (docs/formats.md lists them for users):
//   JOINT or JOINT_deg        position of each joint of Model::joints, rad or m
//                             (JOINT_deg: a revolute joint in degrees); required
//   JOINT_vel, JOINT_acc      their velocities and accelerations: every joint or
//                             none, both or neither (a revolute joint's also as
//                             JOINT_deg_vel, JOINT_deg_acc: deg/s, deg/s^2)
//   wx wy wz dwx dwy dwz      the sensor frame's angular velocity and
//   ax ay az                  acceleration, its origin's acceleration (all nine or none)
//   UP, UP_deg, UP_vel, UP_acc  the joints above the sensor link
//                             (Model::upstream_joints): all or none, as above
//   qx qy qz qw | r11..r33,   the sensor's pose instead (with_pose_columns: they
//   x y z                     are then the model's upstream joints)
//   fx fy fz mx my mz         the measured wrench: all six or none
//   gx gy gz                  gravity in the sensor frame, m/s^2: all or none;
//                             without them gravity comes from the upstream
//                             joints (and the root gravity), else from the
//                             tilt columns, else along the measured force
//                             (paper eq. 37)
//   tilt_x_deg tilt_y_deg     the platform's tilt as design's plans write it,
//                             degrees (read in rad): both or none; without
//                             gx,gy,gz, beside upstream joints an error (both
//                             would turn gravity); else every reader turns
//                             the level gravity by it (tilted_gravity): the
//                             one rule tilt_level_gravity (SampleOptions::
//                             level_gravity, else root_gravity through the
//                             fixed joints above the sensor link)
//   t                         time, s
//   block                     an integer: the sensor re-zeroed between blocks
// Other columns are ignored. A column of another name is read as a role when
// SampleOptions::columns binds it (ROLE=NAME), or, for the wrench, when its
// name is a recorder's common spelling (wrench_spelling, the one table) and
// fx..mz are absent.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::detail {

// A column and the factor its numbers are multiplied by (pi/180 for JOINT_deg, else 1).
struct BoundColumn {
  int column = -1;
  double scale = 1.0;
};
using ColumnGroup = std::vector<BoundColumn>;  // empty: the group is absent

enum class GravityFrom {
  Columns,         // gx, gy, gz
  UpstreamJoints,  // the joints above the sensor link turn the root gravity
  Tilt,            // tilt_x_deg, tilt_y_deg turn the level gravity (tilt_level_gravity)
  Force,           // the measured force's direction (eq. 37)
};

// What a header provides, column by column.
struct ColumnMap {
  ColumnGroup q;                          // [num_joints] Model::joints order (always there)
  ColumnGroup qd, qdd;                    // [num_joints] JOINT_vel, JOINT_acc (both or neither)
  ColumnGroup sensor_motion;              // [9] wx wy wz dwx dwy dwz ax ay az
  ColumnGroup q_upstream;                 // [num_upstream] Model::upstream_joints order
  ColumnGroup qd_upstream, qdd_upstream;  // [num_upstream] (only with q_upstream; both or neither)
  ColumnGroup wrench;                     // [6] fx fy fz mx my mz
  ColumnGroup gravity;                    // [3] gx gy gz
  ColumnGroup tilt;                       // [2] tilt_x_deg tilt_y_deg, scale pi/180
  int time = -1, block = -1;              // columns t, block; -1 when absent
  GravityFrom gravity_from = GravityFrom::Columns;
  // column_note's text: "" when every column read is read under its own name
  // and no group was ignored.
  std::string note;
  // [columns] the role each column is read as (its own name unless bound or
  // spelled otherwise; "" for a column a binding displaced or a group ignored).
  std::vector<std::string> roles;
  // Columns not read, under their own names (a misspelled joint among them).
  std::vector<std::string> unread;
};

// Binds `header` (the column names) to `model`, with the roles that
// options.columns gives other names. `where` starts every message (the
// header's "file:line", or the arrays' name). InputError for a bad binding
// (ColumnNames), a missing joint, a group given in part (the sensor motion
// wx..az only when `sensor_motion`: otherwise it is ignored, with a note),
// _vel without _acc (or the reverse), no wrench when it is required (listing
// the header and proposing the binding), no gravity at all.
ColumnMap map_columns(const Model& model, const std::vector<std::string>& header,
                      const std::string& where, WrenchColumns wrench, const ColumnNames& names = {},
                      bool sensor_motion = true);

// The level gravity that tilt columns turn (tilt_level_gravity,
// read_samples.hpp) when `from` is GravityFrom::Tilt; otherwise zero, and
// options.level_gravity given is an InputError starting with `where` (it would
// go unused: the file's gravity comes from elsewhere). Every reader's one call
// (samples_of, csv_stream's binding, and through it the compensator).
Eigen::Vector3d level_gravity_of(const Model& model, GravityFrom from, const SampleOptions& options,
                                 const std::string& where);

// The joints of model.joints (below the sensor link) that `header` has no
// position column for (JOINT, JOINT_deg, or a role `names` binds), each at
// its reference position: 0, or the limit nearest to 0 when 0 is outside the
// limits. Model::joints order.
std::vector<std::pair<std::string, double>> unlogged_joints(const Model& model,
                                                            const std::vector<std::string>& header,
                                                            const ColumnNames& names);

// The model a header asks for: with the sensor's pose from its columns
// (with_sensor_pose) when it has qx,qy,qz,qw or r11..r33 (under their names,
// or bound by `names`), optionally x,y,z; else `model` as it is. InputError
// (starting with `where`) for a pose in part (some of a group), both a
// quaternion and a matrix, or a pose beside another source of gravity or of
// the sensor frame's motion: gx,gy,gz, tilt_x_deg,tilt_y_deg, wx..az, the
// joints above the sensor link. A model whose pose is set already is
// returned as it is.
Model with_pose_columns(Model model, const std::vector<std::string>& header,
                        const std::string& where, const ColumnNames& names);

// The wrench role (0..5: fx fy fz mx my mz) a recorder's spelling of a column
// name stands for, or -1 (the canonical names themselves: -1). The one table
// of spellings (read_samples.hpp's ColumnNames lists them).
int wrench_spelling(const std::string& name);

// The column of `joint` with `suffix` ("", "_vel", "_acc") as every reader
// binds it: NAME + suffix, else a revolute joint's NAME_deg + suffix (deg,
// deg/s, deg/s^2: read in rad, rad/s, rad/s^2, the scale); column -1 for neither.
BoundColumn joint_column(const Joint& joint, const std::vector<std::string>& header,
                         const std::string& suffix);

// The position columns of `joints` alone (by name, or NAME_deg for a revolute
// joint); InputError for a joint without one.
ColumnGroup position_columns(const std::vector<Joint>& joints,
                             const std::vector<std::string>& header, const std::string& where);

}  // namespace massid::detail

// Samples: the numeric content of a plan or data file, bound to a model.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/csv.hpp"
#include "massid/model.hpp"

namespace massid {

constexpr double kStandardGravity = 9.80665;  // m/s^2

// One sample type for rest and motion. Optional parts have 0 columns when absent.
struct Samples {
  std::string source;
  // Joint stage (Model::joints order; Model::upstream_joints for the *_upstream ones).
  Eigen::MatrixXd q;    // [N x num_joints] joint positions, rad or m
  Eigen::MatrixXd qd;   // [N x num_joints] velocities (JOINT_vel), rad/s or m/s; 0 cols at rest
  Eigen::MatrixXd qdd;  // [N x num_joints] accelerations (JOINT_acc); 0 cols at rest
  Eigen::MatrixXd
      q_upstream;  // [N x num_upstream] joints above the sensor link; 0 cols when absent
  Eigen::MatrixXd qd_upstream;   // [N x num_upstream] their velocities; 0 cols when absent
  Eigen::MatrixXd qdd_upstream;  // [N x num_upstream] their accelerations; 0 cols when absent
  // Sensor-frame stage (sensor frame coordinates).
  Eigen::MatrixXd gravity;        // [N x 3] gravity acceleration, m/s^2
  Eigen::MatrixXd sensor_motion;  // [N x 9] wx wy wz, dwx dwy dwz (rad/s, rad/s^2), ax ay az
                                  // (origin acceleration without gravity, m/s^2); 0 cols: at rest
  // Measurement.
  Eigen::MatrixXd wrench;  // [N x 6] fx fy fz mx my mz; 0 columns when absent
  std::vector<int> line;   // [N] file line of each sample
  Eigen::VectorXd time;    // [N] column t, s (0 rows when absent)
  std::vector<int> block;  // [N] column block: sensor re-zeroed between blocks (empty when absent)
  bool gravity_from_force = false;     // gravity taken from the force direction (eq. 37)
  bool gravity_from_upstream = false;  // gravity from the upstream joints and the root gravity
  bool derivatives_filtered = false;   // qd, qdd derived from positions (motion_filter.hpp)
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};  // root frame, for the upstream joints

  int size() const { return static_cast<int>(q.rows()); }
  bool has_wrench() const { return wrench.cols() == 6; }
  // Joint velocities and accelerations present (a motion log).
  bool has_motion() const { return qd.cols() > 0 || sensor_motion.cols() > 0; }
  bool has_sensor_motion() const { return sensor_motion.cols() == 9; }
};

// Calls f(matrix) on each per-row array of the joint stream: q, qd, qdd, the
// upstream ones, gravity and sensor_motion (not the wrench, time, line, block).
// The one list of them for code that selects or moves rows (rest_windows.hpp,
// delay.hpp).
template <class F>
void for_each_joint_stream_array(Samples& s, F f) {
  for (Eigen::MatrixXd* m : {&s.q, &s.qd, &s.qdd, &s.q_upstream, &s.qd_upstream, &s.qdd_upstream,
                             &s.gravity, &s.sensor_motion})
    f(*m);
}

enum class WrenchColumns { Required, Optional };

// What a reader takes from a file beyond its columns.
struct SampleOptions {
  double g0 = kStandardGravity;  // |g| for gravity from the force direction (eq. 37)
  // Gravity in the URDF root frame, for a sensor below movable joints whose
  // columns the file has (used when the file has no gx,gy,gz).
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
};

// The columns of a data file and what each means: src/column_map.hpp (the one
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

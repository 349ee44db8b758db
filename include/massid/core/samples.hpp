// Samples: the numeric content of a plan or data file, bound to a model.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/gravity.hpp"
#include "massid/core/model.hpp"

namespace massid {

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
  // Filtered rows (motion_filter.hpp, correlated_rows): the noise of rows up
  // to this many apart in one run (consecutive rows, equal block or no block
  // column) may correlate; the fit's covariance accounts for it. 0:
  // independent rows.
  int noise_lags = 0;

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

}  // namespace massid

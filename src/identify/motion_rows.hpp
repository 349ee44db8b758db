// The mass columns of the motion base regressor for one sample, computed
// directly in the sensor frame: the streaming identifier's fast path for
// base_regressor's motion form (base_regressor.hpp), which builds the full
// standard regressor and reduces it. Equal to it to round-off (tested).
//
// Kinematics come from forward_kinematics (kinematics.hpp, the one recursion);
// with the link's rotation R (columns r_k), origin p, and its angular velocity
// w = R w_l, angular acceleration dw = R dw_l and origin acceleration minus
// gravity a = R a_l turned into sensor coordinates, the columns of
// regressor.hpp are
//   mass:          f = -a,                          m = p x f
//   first moment:  f = -(dw x r_k + w x (w x r_k)),  m = -(r_k x a) + p x f
//   inertia:       f = 0,  m = -(R L(dw_l) + w x R L(w_l))   (L: regressor.cpp)
// and a mass other than the sensor link's stands for m_l - m_sensor (whose
// moment rows are zero): the total mass is its own column.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"

namespace massid::detail {

class MotionRows {
 public:
  MotionRows(const Model& model, const BaseParameters& base);

  // out[6 i + a]: row a (fx .. mz) of mass unknown i. q [num_joints],
  // gravity [3] in the sensor frame; qd, qdd [num_joints] and sensor [9]
  // (wx wy wz, dwx dwy dwz, ax ay az) may be null (zero). No allocation.
  void compute(const double* q, const double* qd, const double* qdd, const double* gravity,
               const double* sensor, double* out);

 private:
  struct Col {
    int link, kind;
  };
  // Sensor-frame motion of one link, for the columns that need it.
  struct Frame {
    Eigen::Vector3d w, dw, a;
    Eigen::Vector3d wr[3];  // w x r_k
  };

  const Model* model_;
  std::vector<Col> cols_;
  std::vector<char> first_, inertia_;  // [num_links] columns of these kinds are wanted
  KinematicsData data_;                // workspace of forward_kinematics
  std::vector<Frame> frames_;          // [num_links]
  Eigen::VectorXd zero_;               // [num_joints] zeros: qd, qdd when absent
};

}  // namespace massid::detail

// The regressor of the base parameters (and sensor offsets):
//
//   w = Y_b(q, g) [pi_b; w_0],   Y_b = [Y'(q, g)[:, B]   I_6]      (paper eq. 29)
//
// with Y' and B as in base_parameters.hpp. This is the row block that the
// estimator stacks (eq. 33) for every sample.
#pragma once

#include <Eigen/Core>

#include "massid/base_parameters.hpp"
#include "massid/kinematics.hpp"
#include "massid/model.hpp"

namespace massid {

// Workspace of base_regressor. Sized by the constructor; no allocation later.
struct RegressorData {
  RegressorData(const Model& model, const BaseParameters& base);
  KinematicsData kinematics;  // link poses of the current sample
  Eigen::MatrixXd standard;   // [6 x num_standard] Y(q, g)
  Eigen::MatrixXd base;       // [6 x num_unknowns] Y_b(q, g), the result
};

// Fills data.base for joint positions q and gravity g (sensor frame).
void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g);

}  // namespace massid

// The regressor of the base parameters (and sensor offsets):
//
//   w = Y_b [pi_b; w_0],   Y_b = [Y'[:, B]   I_6]      (paper eq. 29)
//
// with Y' and B as in base_parameters.hpp: Y' is the standard regressor
// (regressor.hpp) at rest, Y(q, g), or in motion, Y(q, qd, qdd, g, sensor
// motion), in the layout of the base parameters. This is the row block that
// the estimator stacks (eq. 33) for every sample.
#pragma once

#include <Eigen/Core>

#include "massid/core/base_parameters.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"

namespace massid {

// Workspace of base_regressor. Sized by the constructor; no allocation later.
struct RegressorData {
  RegressorData(const Model& model, const BaseParameters& base);
  KinematicsData kinematics;  // link poses (and motion) of the current sample
  Eigen::MatrixXd standard;   // [6 x layout.size(model)] Y, the standard regressor
  Eigen::MatrixXd base;       // [6 x num_unknowns] Y_b, the result
};

// At rest: joint positions q [num_joints] and gravity g (sensor frame).
void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g);

// In motion (base.motion()): q, qd, qdd [num_joints], gravity and the sensor
// frame's own motion (sensor frame).
void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q,
                    const Eigen::Ref<const Eigen::VectorXd>& qd,
                    const Eigen::Ref<const Eigen::VectorXd>& qdd, const Eigen::Vector3d& g,
                    const FrameMotion& sensor);

// Sample i of `samples`, at rest or in motion as base requires (a static
// sample in a motion model: zero velocities; samples without sensor motion:
// the sensor at rest).
void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Samples& samples, int i);

// The sensor frame's motion of sample i (at rest when the samples have none).
FrameMotion sensor_motion(const Samples& samples, int i);

}  // namespace massid

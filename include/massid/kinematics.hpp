// Forward kinematics of the measured links in the sensor frame.
//
//   T_l(q) = T_parent(l)(q) * origin_l * motion_l(q_l)          (paper eqs. 20-23)
//
// motion is a rotation about the joint axis (revolute) or a translation along
// it (prismatic); the sensor link's frame is the sensor frame (T = identity).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/model.hpp"

namespace massid {

// Workspace of forward_kinematics. Sized once by the constructor; the
// algorithm never allocates.
struct KinematicsData {
  explicit KinematicsData(const Model& model);
  std::vector<Eigen::Matrix3d> rotation;  // [num_links] R_l: link frame -> sensor frame
  std::vector<Eigen::Vector3d> position;  // [num_links] p_l: link origin in the sensor frame
};

// q: [num_joints] joint positions, in Model::joints order.
void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q);

}  // namespace massid

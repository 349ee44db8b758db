#include "massid/kinematics.hpp"

#include <Eigen/Geometry>

namespace massid {

KinematicsData::KinematicsData(const Model& model)
    : rotation(model.links.size(), Eigen::Matrix3d::Identity()),
      position(model.links.size(), Eigen::Vector3d::Zero()) {}

void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q) {
  data.rotation[0].setIdentity();
  data.position[0].setZero();
  for (int l = 1; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    const Eigen::Matrix3d& Rp = data.rotation[link.parent];
    Eigen::Matrix3d R = Rp * link.origin.linear();
    Eigen::Vector3d p = data.position[link.parent] + Rp * link.origin.translation();
    if (link.type == JointType::Revolute) {
      R = R * Eigen::AngleAxisd(q[link.joint_index], link.axis).toRotationMatrix();
    } else if (link.type == JointType::Prismatic) {
      p += R * (q[link.joint_index] * link.axis);
    }
    data.rotation[l] = R;
    data.position[l] = p;
  }
}

}  // namespace massid

// Private: what the gravity and the motion predictor share when they compile a
// model into rigid bodies: the folding of links into bodies (a link joined by
// a fixed joint belongs to its parent's body), the joint frame turned so that
// its axis is z, and the bodies' depth-first order.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "massid/core/model.hpp"

namespace massid::detail {

// A rotation C with C e_z = axis (unit): the joint frame turned so that its
// axis is z.
inline Eigen::Matrix3d axis_to_z(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized())
      .toRotationMatrix();
}

// What every body of a predictor has; the predictors derive their bodies from it.
struct TreeBody {
  int parent = -1, joint = 0;
  double joint_scale = 1.0, joint_offset = 0.0;  // a mimic joint follows its master
  JointType type = JointType::Fixed;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // A_k
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   // t_k
  std::vector<int> children;
};

// The rigid bodies of a model, body 0 the sensor's, before depth-first numbering.
template <class Body>
struct BodyTree {
  std::vector<Body> bodies;                // [bodies]
  std::vector<int> body_of;                // [links] the body link l belongs to
  std::vector<Eigen::Isometry3d> in_body;  // [links] link l's frame in its body's frame
};

// Folds the links into bodies. For each movable link l, orient(b, l,
// to_joint) sets the body's orientation (b.rotation and what else the body
// keeps) from to_joint, l's joint frame in the parent body's frame, and
// returns the orientation of l's frame in the new body's frame.
template <class Body, class Orient>
BodyTree<Body> fold_fixed_links(const Model& model, Orient orient) {
  BodyTree<Body> tree{
      std::vector<Body>(1), std::vector<int>(model.num_links(), 0),
      std::vector<Eigen::Isometry3d>(model.num_links(), Eigen::Isometry3d::Identity())};
  for (int l = 1; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    const Eigen::Isometry3d to_joint = tree.in_body[link.parent] * link.origin;
    if (link.type == JointType::Fixed) {
      tree.body_of[l] = tree.body_of[link.parent];
      tree.in_body[l] = to_joint;
      continue;
    }
    Body b;
    b.parent = tree.body_of[link.parent];
    b.joint = link.joint_index;
    b.joint_scale = link.joint_scale;
    b.joint_offset = link.joint_offset;
    b.type = link.type;
    b.translation = to_joint.translation();
    tree.in_body[l].linear() = orient(b, l, to_joint);
    tree.body_of[l] = static_cast<int>(tree.bodies.size());
    tree.bodies[b.parent].children.push_back(tree.body_of[l]);
    tree.bodies.push_back(std::move(b));
  }
  return tree;
}

// Bodies (each with its `children`) in depth-first order from body 0,
// children in their original order.
template <class Body>
std::vector<int> depth_first(const std::vector<Body>& bodies) {
  std::vector<int> order, stack{0};
  while (!stack.empty()) {
    const int b = stack.back();
    stack.pop_back();
    order.push_back(b);
    for (auto c = bodies[b].children.rbegin(); c != bodies[b].children.rend(); ++c)
      stack.push_back(*c);
  }
  return order;
}

}  // namespace massid::detail

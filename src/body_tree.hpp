// Private: what the gravity and the motion predictor share when they compile a
// model into rigid bodies (a link joined by a fixed joint belongs to its
// parent's body): the joint frame turned so that its axis is z, and the
// bodies' depth-first order.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace massid::detail {

// A rotation C with C e_z = axis (unit): the joint frame turned so that its
// axis is z.
inline Eigen::Matrix3d axis_to_z(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized())
      .toRotationMatrix();
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

// The arm around a wrist sensor as design checks it (a sensor link below
// movable joints, Model::upstream): the height of its moving points above the
// floor and its distance from itself. Internal to design.
//
// Floor: the plane through the URDF root frame's origin normal to the root
// gravity (z = 0 for gravity along -z). Checked against it: the origins of
// the links above the sensor whose height changes with the joints, and the
// tool's points (the measured
// links' origins, centres of mass and collision spheres, less their radius).
//
// Self: the arm as a chain of bodies, one per movable joint above the sensor
// (plus the root's): each body is the polyline through the origins of its
// links, from its joint to the next joint; the last body carries the tool
// (segments from the sensor origin to the tool's points). The clearance is
// the least distance between the polylines of two bodies that no single body
// joins (bodies i and j with |i - j| >= 2): a capsule check whose D is about
// the sum of two links' radii.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"

namespace massid {

// A point checked for clearance: a link origin, a centre of mass or a
// primitive collision shape's bounding sphere (link frame; radius 0 for a point).
struct ClearancePoint {
  int link;
  Eigen::Vector3d p;
  double radius;
};

// Every link's points, in link order.
std::vector<ClearancePoint> clearance_points(const Model& model);

// Which of `count` heights change with the joints: heights(q, h) fills h
// [count] at six random positions q of `joints` (a point that moves at a
// constant height stays where the mount puts it).
template <class Heights>
std::vector<bool> heights_vary(const std::vector<Joint>& joints, std::size_t count,
                               Heights heights) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd q(joints.size());
  std::vector<double> first(count), h(count);
  std::vector<bool> varies(count, false);
  for (int trial = 0; trial < 6; ++trial) {
    for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = joints[j].generic_position(u(rng));
    heights(q, h);
    for (std::size_t i = 0; i < count; ++i) {
      if (trial == 0) first[i] = h[i];
      if (std::abs(h[i] - first[i]) > 1e-9) varies[i] = true;
    }
  }
  return varies;
}

struct ArmClearanceValue {
  double height = 0.0;  // m, lowest checked point above the floor (+inf: nothing moves)
  std::string low_link;
  double self = 0.0;      // m, least distance between non-adjacent bodies (+inf: no such pair)
  std::string self_pair;  // "A / B", the two bodies (or tool links)
};

class ArmClearance {
 public:
  ArmClearance(const Model& model, const Eigen::Vector3d& root_gravity);
  // qu [num_upstream_joints], q [num_joints].
  ArmClearanceValue at(const Eigen::Ref<const Eigen::VectorXd>& qu,
                       const Eigen::Ref<const Eigen::VectorXd>& q);

 private:
  const Model& model_;
  Eigen::Vector3d up_;
  std::vector<int> body_of_step_;       // [upstream.size()] body of each step's child link
  std::vector<bool> step_moves_;        // [upstream.size()] a movable joint at or above it
  std::vector<std::string> body_name_;  // the root link, then "the link moved by 'J'"
  int tool_body_ = 0;
  std::vector<ClearancePoint> tool_;
  std::vector<Eigen::Isometry3d> poses_;
  KinematicsData kin_;
};

}  // namespace massid

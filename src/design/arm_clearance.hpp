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
#include <string>
#include <vector>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"

namespace massid {

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

  // Distance between segments [p0, p1] and [q0, q1].
  static double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

 private:
  const Model& model_;
  Eigen::Vector3d up_;
  std::vector<int> body_of_step_;       // [upstream.size()] body of each step's child link
  std::vector<bool> step_moves_;        // [upstream.size()] a movable joint at or above it
  std::vector<std::string> body_name_;  // the root link, then "the link moved by 'J'"
  int tool_body_ = 0;
  struct ToolPoint {
    int link;
    Eigen::Vector3d p;  // link frame
    double radius;
  };
  std::vector<ToolPoint> tool_;
  std::vector<Eigen::Isometry3d> poses_;
  KinematicsData kin_;
};

}  // namespace massid

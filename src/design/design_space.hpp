// The set of poses a plan may use: joints within their (narrowed) limits,
// platform tilts (a list or a cone) and the minimum height of the
// moving link origins above the platform plane. Internal to design.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "design/arm_clearance.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/design/design.hpp"

namespace massid {

class DesignSpace {
 public:
  DesignSpace(const Model& model, const DesignOptions& options);

  // A random feasible pose; InputError when none is found after many tries.
  // `level`: at the level tilt (PlanPose::level), for the reserved level poses.
  PlanPose sample(std::mt19937_64& rng, bool level = false);
  // Whether the level tilt is among the allowed ones (always within a cone),
  // and whether any other is.
  bool level_allowed() const;
  bool tilts_other_than_level() const;
  // The lowest clearance of the checked points above the platform plane at q
  // (m; +inf when nothing moves), and which link it belongs to.
  double clearance(const Eigen::VectorXd& q, int* link = nullptr);
  // The same for a pose, naming what is lowest (a wrist: above the floor).
  double clearance(const PlanPose& pose, std::string* what);
  // The default minimum height is dropped when no random pose satisfies it
  // (a sensor link below the arm's mount, say); `required`: the user asked
  // for it, keep it (sample() then fails with its message).
  void relax_min_height_if_infeasible(bool required);
  bool min_height_relaxed() const { return relaxed_; }
  // Continuous coordinates of a pose: free joints, then its own tilt x, y
  // when every pose may have its own tilt (a cone without tilt groups).
  int dimension() const { return static_cast<int>(free_.size()) + (own_tilt() ? 2 : 0); }
  bool own_tilt() const { return cone_ && groups_ == 0; }
  Eigen::VectorXd coordinates(const PlanPose& pose) const;
  // The pose at coordinates x (clamped to the limits and the cone), keeping
  // `like`'s listed tilt; false when it violates the minimum height.
  bool pose_at(const Eigen::VectorXd& x, const PlanPose& like, PlanPose& out);
  // Initial pattern-search step of each coordinate.
  Eigen::VectorXd steps() const;
  const Eigen::Vector3d& level() const { return level_; }

  // Shared tilts (PlanPose::group indexes them): the listed tilts, or the
  // tilt groups within a cone, which the optimiser may move (set_tilt clamps
  // to the cone).
  int num_tilts() const { return static_cast<int>(tilts_.size()); }
  bool tilts_adjustable() const { return cone_ && groups_ > 0; }
  const Tilt& tilt(int k) const { return tilts_[k]; }
  Tilt set_tilt(int k, Tilt t);
  double tilt_max() const { return tilt_max_; }

 private:
  bool high_enough(const PlanPose& pose);
  // A wrist: the arm's joints, their gravity and its clearances (design_space.cpp's end).
  void init_arm(const DesignOptions& o);
  void arm_pose(PlanPose& pose) const;

  const Model& model_;
  Eigen::Vector3d level_;
  struct Free {
    int joint;  // index into q, or for the arm's into q_upstream
    double lo, hi;
    bool arm = false;  // a wrist: a joint above the sensor
  };
  // The free joint's position in the pose (const or not).
  template <class Pose>
  static auto& position(Pose& pose, const Free& f) {
    return f.arm ? pose.q_upstream[f.joint] : pose.q[f.joint];
  }
  template <class Empty>
  static Free narrowed(int j, const Joint& joint, double margin, const DesignOptions& o,
                       Empty empty);
  std::vector<Free> free_;  // the model's joints, then (a wrist) the arm's
  std::optional<ArmClearance> arm_;
  Eigen::Vector3d root_gravity_ = Eigen::Vector3d::Zero();
  std::optional<double> self_clearance_;
  bool cone_ = false;
  double tilt_max_ = 0.0;
  int groups_ = 0;           // tilt groups within the cone; 0: a tilt per pose
  std::vector<Tilt> tilts_;  // listed tilts or tilt groups (level only when neither)
  std::optional<double> min_height_;
  // Points checked against the minimum height: those that move with the joints.
  std::vector<ClearancePoint> points_;
  int level_group_ = -1;
  bool relaxed_ = false;  // index of the level tilt in a list, -1: none (or a cone)
  KinematicsData kin_;
};

}  // namespace massid

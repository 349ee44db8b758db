// The set of poses a plan may use: joints within their (narrowed) limits,
// platform tilts (a list or a cone) and the minimum height of the
// moving link origins above the platform plane. Internal to design.
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "massid/design.hpp"
#include "massid/kinematics.hpp"
#include "massid/model.hpp"

namespace massid {

class DesignSpace {
 public:
  DesignSpace(const Model& model, const DesignOptions& options);

  // A random feasible pose; InputError when none is found after many tries.
  PlanPose sample(std::mt19937_64& rng);
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
  bool high_enough(const Eigen::VectorXd& q);
  Tilt clamp_to_cone(Tilt t) const;

  const Model& model_;
  Eigen::Vector3d level_;
  struct Free {
    int joint;
    double lo, hi;
  };
  std::vector<Free> free_;
  bool cone_ = false;
  double tilt_max_ = 0.0;
  int groups_ = 0;           // tilt groups within the cone; 0: a tilt per pose
  std::vector<Tilt> tilts_;  // listed tilts or tilt groups (level only when neither)
  std::optional<double> min_height_;
  std::vector<int> moving_links_;  // links whose origin moves with the joints
  KinematicsData kin_;
};

}  // namespace massid

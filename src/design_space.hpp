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
  // Continuous coordinates of a pose: free joints, then (cone) tilt x, y.
  int dimension() const { return static_cast<int>(free_.size()) + (cone_ ? 2 : 0); }
  Eigen::VectorXd coordinates(const PlanPose& pose) const;
  // The pose at coordinates x (clamped to the limits and the cone), keeping
  // `like`'s listed tilt; false when it violates the minimum height.
  bool pose_at(const Eigen::VectorXd& x, const PlanPose& like, PlanPose& out);
  // Initial pattern-search step of each coordinate.
  Eigen::VectorXd steps() const;
  double level_angle(const Tilt& t) const { return tilt_angle(level_, t); }
  const Eigen::Vector3d& level() const { return level_; }

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
  std::vector<Tilt> tilts_;  // listed tilts (level only when empty and no cone)
  std::optional<double> min_height_;
  std::vector<int> moving_links_;  // links whose origin moves with the joints
  KinematicsData kin_;
};

}  // namespace massid

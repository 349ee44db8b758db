#include "plan_order.hpp"

#include <algorithm>
#include <cmath>

namespace massid {
namespace {

double gravity_angle(const PlanPose& a, const PlanPose& b) {
  return std::atan2(a.gravity.cross(b.gravity).norm(), a.gravity.dot(b.gravity));
}

double cost(const PlanPose& a, const PlanPose& b) {
  const double tilt = gravity_angle(a, b);
  return (tilt > 1e-9 ? 1000.0 : 0.0) + 100.0 * tilt + (a.q - b.q).cwiseAbs().sum();
}

}  // namespace

std::vector<PlanPose> order_plan(std::vector<PlanPose> poses) {
  const size_t n = poses.size();
  if (n < 3) return poses;
  // Nearest neighbour from the least tilted pose.
  size_t first = 0;
  for (size_t i = 1; i < n; ++i)
    if (std::hypot(poses[i].tilt.x, poses[i].tilt.y) <
        std::hypot(poses[first].tilt.x, poses[first].tilt.y))
      first = i;
  std::swap(poses[0], poses[first]);
  for (size_t i = 1; i < n; ++i) {
    size_t best = i;
    for (size_t k = i + 1; k < n; ++k)
      if (cost(poses[i - 1], poses[k]) < cost(poses[i - 1], poses[best])) best = k;
    std::swap(poses[i], poses[best]);
  }
  // 2-opt on the open path (the first pose stays first).
  for (bool improved = true; improved;) {
    improved = false;
    for (size_t i = 1; i + 1 < n; ++i) {
      for (size_t k = i + 1; k < n; ++k) {
        const double before =
            cost(poses[i - 1], poses[i]) + (k + 1 < n ? cost(poses[k], poses[k + 1]) : 0.0);
        const double after =
            cost(poses[i - 1], poses[k]) + (k + 1 < n ? cost(poses[i], poses[k + 1]) : 0.0);
        if (after < before - 1e-12) {
          std::reverse(poses.begin() + i, poses.begin() + k + 1);
          improved = true;
        }
      }
    }
  }
  return poses;
}

PlanTravel plan_travel(const std::vector<PlanPose>& poses) {
  PlanTravel t;
  for (size_t i = 1; i < poses.size(); ++i) {
    if (gravity_angle(poses[i - 1], poses[i]) > 1e-9) ++t.tilt_changes;
    t.joint_travel += (poses[i].q - poses[i - 1].q).cwiseAbs().sum();
  }
  return t;
}

}  // namespace massid

// The order in which to run a plan: few and small platform tilts (slow and the
// risky part of the experiment), then short joint travel. Internal to design.
#pragma once

#include <vector>

#include "massid/design/design.hpp"

namespace massid {

// Poses grouped by tilt (equal gravity direction): the tilts from the least
// tilted on, each next the nearest; within a tilt an open path of short joint
// travel (sum |dq|: nearest neighbour, then 2-opt) starting near the previous
// tilt's last pose. Tilt changes: one fewer than distinct tilts.
std::vector<PlanPose> order_plan(std::vector<PlanPose> poses);

struct PlanTravel {
  int tilt_changes = 0;       // consecutive poses with different gravity
  double joint_travel = 0.0;  // sum of |dq| over the path
};
PlanTravel plan_travel(const std::vector<PlanPose>& poses);

}  // namespace massid

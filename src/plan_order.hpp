// The order in which to run a plan: few and small platform tilts (slow and the
// risky part of the experiment), then short joint travel. Internal to design.
#pragma once

#include <vector>

#include "massid/design.hpp"

namespace massid {

// Open path through the poses: nearest neighbour from the least tilted pose,
// then 2-opt, on the cost  1000 [tilt changes] + 100 |gravity angle change| + sum |dq|.
std::vector<PlanPose> order_plan(std::vector<PlanPose> poses);

struct PlanTravel {
  int tilt_changes = 0;       // consecutive poses with different gravity
  double joint_travel = 0.0;  // sum of |dq| over the path
};
PlanTravel plan_travel(const std::vector<PlanPose>& poses);

}  // namespace massid

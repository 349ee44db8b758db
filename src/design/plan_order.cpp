#include "design/plan_order.hpp"

#include <algorithm>
#include <cmath>

namespace massid {
namespace {

double gravity_angle(const PlanPose& a, const PlanPose& b) {
  return std::atan2(a.gravity.cross(b.gravity).norm(), a.gravity.dot(b.gravity));
}

// The joints' travel, the arm's above a wrist sensor included.
double joint_distance(const PlanPose& a, const PlanPose& b) {
  const double arm = a.q_upstream.size() == b.q_upstream.size() && a.q_upstream.size() > 0
                         ? (a.q_upstream - b.q_upstream).cwiseAbs().sum()
                         : 0.0;
  return (a.q - b.q).cwiseAbs().sum() + arm;
}

// A wrist: the arm turns gravity in the sensor frame, no platform tilts.
bool moves_arm(const std::vector<PlanPose>& poses) {
  return !poses.empty() && poses.front().q_upstream.size() > 0;
}

// Reorders `items` as the nearest-neighbour path on the distance d from items[first].
template <class T, class Distance>
void nearest_neighbour_path(std::vector<T>& items, size_t first, Distance d) {
  std::swap(items[0], items[first]);
  for (size_t i = 1; i < items.size(); ++i) {
    size_t best = i;
    for (size_t k = i + 1; k < items.size(); ++k)
      if (d(items[i - 1], items[k]) < d(items[i - 1], items[best])) best = k;
    std::swap(items[i], items[best]);
  }
}

// Open path through `poses` from the one nearest to `from`: nearest neighbour,
// then 2-opt on the given distance.
template <class Distance>
void order_path(std::vector<PlanPose>& poses, const PlanPose* from, Distance d) {
  const size_t n = poses.size();
  if (n < 2) return;
  size_t first = 0;
  if (from)
    for (size_t i = 1; i < n; ++i)
      if (d(*from, poses[i]) < d(*from, poses[first])) first = i;
  nearest_neighbour_path(poses, first, d);
  const size_t keep = from ? 0 : 1;  // without a predecessor the first pose may move too
  for (bool improved = true; improved;) {
    improved = false;
    for (size_t i = std::max<size_t>(1, keep); i + 1 < n; ++i) {
      for (size_t k = i + 1; k < n; ++k) {
        const double tail_before = k + 1 < n ? d(poses[k], poses[k + 1]) : 0.0;
        const double tail_after = k + 1 < n ? d(poses[i], poses[k + 1]) : 0.0;
        if (d(poses[i - 1], poses[k]) + tail_after <
            d(poses[i - 1], poses[i]) + tail_before - 1e-12) {
          std::reverse(poses.begin() + i, poses.begin() + k + 1);
          improved = true;
        }
      }
    }
  }
}

}  // namespace

std::vector<PlanPose> order_plan(std::vector<PlanPose> poses) {
  if (moves_arm(poses)) {  // one path of short joint travel
    order_path(poses, nullptr, joint_distance);
    return poses;
  }
  // Groups of poses with the same gravity direction (the same tilt).
  std::vector<std::vector<PlanPose>> groups;
  for (PlanPose& p : poses) {
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const auto& grp) { return gravity_angle(grp.front(), p) < 1e-9; });
    if (g == groups.end())
      groups.push_back({p});
    else
      g->push_back(p);
  }
  // Tilts: from the least tilted, each next the nearest in gravity direction.
  const auto tilt = [](const std::vector<PlanPose>& g) {
    return std::hypot(g.front().tilt.x, g.front().tilt.y);
  };
  const auto least =
      std::min_element(groups.begin(), groups.end(),
                       [&](const auto& a, const auto& b) { return tilt(a) < tilt(b); });
  nearest_neighbour_path(groups, least - groups.begin(), [](const auto& a, const auto& b) {
    return gravity_angle(a.front(), b.front());
  });
  // Within each tilt, short joint travel, starting near where the last one ended.
  std::vector<PlanPose> out;
  for (auto& g : groups) {
    order_path(g, out.empty() ? nullptr : &out.back(), joint_distance);
    out.insert(out.end(), g.begin(), g.end());
  }
  return out;
}

PlanTravel plan_travel(const std::vector<PlanPose>& poses) {
  PlanTravel t;
  const bool arm = moves_arm(poses);
  for (size_t i = 1; i < poses.size(); ++i) {
    if (!arm && gravity_angle(poses[i - 1], poses[i]) > 1e-9) ++t.tilt_changes;
    t.joint_travel += joint_distance(poses[i - 1], poses[i]);
  }
  return t;
}

}  // namespace massid

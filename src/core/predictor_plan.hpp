// The compiled form of the gravity predictor (predictor.hpp): the recursion's
// steps and the joint stage's lanes, in the layout the SIMD paths read. Private
// to the library: a Predictor holds it behind a pointer, so that the layout
// can change without changing the public headers or their ABI.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/core/predictor.hpp"

namespace massid::detail {

// One movable body k of the recursion (bodies numbered depth first, 0 the
// sensor body; steps are stored for k = 1..n and run from n down to 1).
struct PredictorStep {
  int joint = 0;                                 // index into q
  double joint_scale = 1.0, joint_offset = 0.0;  // the joint's position: scale q + offset (mimic)
  int parent = 0;                                // parent body p
  bool carry = false;                            // p == k - 1: S_p continues in registers
  bool gathers = false;  // carry, and p has other children: add their sum, gathered[p]
  double slide = 0.0;    // M_k for a prismatic joint, else 0 (c_k's q term)
  // A_k (parent frame <- body frame, joint axis = z): axes[j] = column j, then 0.
  double axes[3][4] = {};
  // Row 2 of A_k as two lane pairs, (A_2x, A_2y) and (A_2y, -A_2x): B_k's row 2.
  double row2[4] = {};
  double constant[4] = {};  // M_k t_k, plus h_p when carry (added once, by p's first child)
  double resume[4] = {};    // not carry: h_{k-1} (body k - 1 is a leaf), where S restarts
};

struct PredictorPlan {
  std::vector<PredictorStep> steps;             // [n], steps[k - 1] is body k
  std::vector<Eigen::Vector3d> first_moment;    // [n + 1] h_b, body frame
  std::vector<int> lane_joint;                  // [n, padded to 4] joint of body k (index k - 1)
  // [n, padded to 4] theta = scale q + offset: (1, 0) for a revolute joint (a
  // mimic's multiplier and offset), (0, 0) for a prismatic one and past n.
  std::vector<double> lane_scale, lane_offset;
  int num_gathered = 0;  // 4 (n + 1): PredictorData::gathered's size
  bool four_lanes = false;  // AVX2 path (x86-64 CPUs that have it); same bits as the two-lane path
};

}  // namespace massid::detail

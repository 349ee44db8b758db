// The compiled form of the motion predictor (motion_predictor.hpp): per-body
// arrays in the blocked layout the SIMD paths read. Private to the library: a
// MotionPredictor holds it behind a pointer, so that the layout can change
// without changing the public headers or their ABI.
#pragma once

#include <vector>

#include "massid/core/motion_predictor.hpp"

namespace massid::detail {

// Per-body arrays come in blocks of four bodies, structure of arrays within
// a block: in an array of C components per body, component c of body k is at
// [4 C (k / 4) + 4 c + k % 4]. Bodies 0..num_bodies-1, then padding to
// `lanes` (a multiple of 4: no mass, the identity, no joint).
struct MotionPredictorPlan {
  int num_bodies = 1;             // n + 1: the sensor body and one per movable joint
  int lanes = 4;                  // num_bodies padded to a multiple of 4
  std::vector<int> parent;        // [num_bodies] parent body p (-1 for body 0)
  std::vector<int> axis;          // [num_bodies] 0, 1, 2: turns about that axis of p; 3: B_k
  std::vector<char> general;      // [lanes / 4] 1: a block with a body k > 0 that uses B_k
  std::vector<int> joint;         // [lanes] index into q of body k's joint (0: none)
  std::vector<double> revolute;   // [lanes] sigma_k for a revolute joint, else 0
  std::vector<double> prismatic;  // [lanes] sigma_k for a prismatic joint, else 0
  std::vector<double> angle;      // [lanes] phi_k, added to theta_k (+ a mimic's offset)
  std::vector<double> slide;      // [lanes] a prismatic mimic joint's offset, sigma_k b_k
  std::vector<double> axes;       // [lanes x 9] A_k, row-major (axis e_m: only column 2, e_m)
  std::vector<double> origin;     // [lanes x 3] t_k
  std::vector<double> inertial;   // [lanes x 10] m, hx, hy, hz, ixx, ixy, ixz, iyy, iyz, izz
  bool four_lanes = false;        // AVX2 path (x86-64 CPUs that have it)
};

}  // namespace massid::detail

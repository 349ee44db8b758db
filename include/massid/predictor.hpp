// Real-time prediction of the gravity wrench from identified base parameters
// alone (never from the URDF's inertials):
//
//   f = M_t g + f_0,   m = H(q) x g + m_0,                      (paper eqs. 15, 29)
//   H(q) = sum_b (m_b p_b(q) + R_b(q) h_b)
//
// H is the first moment of the measured bodies in the sensor frame. Links joined
// by fixed joints are folded into one rigid body b; (m_b, h_b) are the base
// parameters mapped onto the bodies (the base parameters' representatives, all
// other standard parameters zero, which gives the same Y_b pi_b).
//
// predict() evaluates H by a backward recursion over subtrees, each body's
// frame turned at compile time so that its joint axis is z:
//
//   S_b = h_b + sum_{k child of b} ( c_k(q) + B_k(q) S_k ),   H = S_0
//   B_k = A_k Rz(theta_k) = [A_k,x cos + A_k,y sin,  A_k,y cos - A_k,x sin,  A_k,z]
//   c_k = M_k t_k + M_k d_k A_k,z
//
// with M_k the sum of m over k's subtree, (A_k, t_k) the joint frame of k in
// its parent's frame, theta_k = q_k for a revolute joint and d_k = q_k for a
// prismatic one. B_k and c_k depend on q_k alone, so they are computed off the
// dependent chain; each step of the chain is one 3x3 product and an addition
// (12 cycles of latency). Bodies are numbered depth first, so along a serial
// run the partial sum S stays in registers; it goes through memory only where
// a branch joins its parent. The sines and cosines of all joints are computed
// together (two lanes at a time); no allocation, no branch on the joint type.
//
// Predictor is immutable and compiled once; PredictorData is the workspace.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/model.hpp"

namespace massid {

using Wrench = Eigen::Matrix<double, 6, 1>;  // fx fy fz mx my mz

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

struct Predictor {
  std::vector<PredictorStep> steps;             // [n], steps[k - 1] is body k
  std::vector<Eigen::Vector3d> first_moment;    // [n + 1] h_b, body frame
  std::vector<int> lane_joint;                  // [n, padded to 4] joint of body k (index k - 1)
  std::vector<double> lane_revolute;            // [n, padded to 4] revolute of body k, 0 past n
  std::vector<double> lane_scale, lane_offset;  // [n, padded to 4] theta = scale q + offset
  double total_mass = 0.0;                      // M_t
  Wrench offset = Wrench::Zero();               // f_0, m_0 (zero without offsets)
  int num_joints = 0;
  bool four_lanes = false;  // AVX2 path (x86-64 CPUs that have it); same bits as the two-lane path
  int num_bodies() const { return static_cast<int>(first_moment.size()); }
};

// values: [num_unknowns] base parameters, then the six offsets when base.offset.
Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values);

// Workspace of predict(), sized once.
struct PredictorData {
  explicit PredictorData(const Predictor& predictor);
  // Joint stage, per movable body k (index k - 1), padded to a multiple of 4:
  std::vector<double> sin;  // sin theta_k
  std::vector<double> cos;  // cos theta_k
  // Recursion stage: [4 (n + 1)] sum of c_k + B_k S_k over the children k of
  // body b that are not its first child (zero between calls), padded to 4.
  std::vector<double> gathered;
};

// Gravity wrench at joint positions q [num_joints] and gravity g (sensor frame).
Wrench predict(const Predictor& predictor, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g);

// Batch form: row i of wrenches [N x 6] from row i of q [N x num_joints] and of
// gravity [N x 3]. Does not allocate.
void predict(const Predictor& predictor, PredictorData& data,
             const Eigen::Ref<const Eigen::MatrixXd>& q,
             const Eigen::Ref<const Eigen::MatrixXd>& gravity,
             Eigen::Ref<Eigen::MatrixXd> wrenches);

}  // namespace massid

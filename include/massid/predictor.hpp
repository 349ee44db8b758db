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
//   S_b = h_b + sum_{k child of b} ( M_k t_k + A_k (Rz(theta_k) S_k + M_k d_k e_z) )
//   H   = S_0
//
// with M_k the sum of m over k's subtree, (A_k, t_k) the joint frame of k in
// its parent's frame, theta_k = q_k for a revolute joint and d_k = q_k for a
// prismatic one. A rotation about z touches two components; the sines and
// cosines of all joints are computed together (vectorised); no allocation, no
// branch on the joint type.
//
// Predictor is immutable and compiled once; PredictorData is the workspace.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/model.hpp"

namespace massid {

using Wrench = Eigen::Matrix<double, 6, 1>;  // fx fy fz mx my mz

struct Predictor {
  // Movable bodies 1..n in parent-first order (body 0, the sensor body, has
  // only first_moment[0]). Arrays are indexed by body.
  std::vector<int> parent;                    // parent body
  std::vector<int> joint;                     // index into q
  std::vector<double> revolute;               // 1 for a revolute joint, else 0 (theta = revolute q)
  std::vector<double> prismatic;              // 1 for a prismatic joint, else 0 (d = prismatic q)
  std::vector<Eigen::Matrix3d> rotation;      // A_k: parent frame <- body frame (joint axis = z)
  std::vector<Eigen::Vector3d> translation;   // t_k: joint origin, parent frame
  std::vector<double> subtree_mass;           // M_k
  std::vector<Eigen::Vector3d> first_moment;  // h_b, body frame
  double total_mass = 0.0;                    // M_t
  Wrench offset = Wrench::Zero();
  int num_joints = 0;
  int num_bodies() const { return static_cast<int>(parent.size()); }
};

// values: [num_unknowns] base parameters, then the six offsets when base.offset.
Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values);

// Workspace of predict(), sized once (per body).
struct PredictorData {
  explicit PredictorData(const Predictor& predictor);
  // Joint stage: angles and their sines and cosines of bodies 1.. (index b - 1),
  // padded to an even length.
  std::vector<double> theta, sin, cos;
  // Recursion: S_b, the first moment of body b's subtree in its frame.
  std::vector<Eigen::Vector3d> subtree;
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

// Real-time prediction of the gravity wrench from identified base parameters
// alone (never from the URDF's inertials):
//
//   f = M_t g,   m = H(q) x g                (paper eqs. 15, 29, without f_0, m_0)
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
#include <memory>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"

namespace massid {

using Wrench = Eigen::Matrix<double, 6, 1>;  // fx fy fz mx my mz

namespace detail {
struct PredictorPlan;  // the compiled recursion (src/core/predictor_plan.hpp)
}

// A compiled gravity predictor: immutable, cheap to copy (copies share the
// plan). Default-constructed it is empty: predict() throws ArgumentError.
struct Predictor {
  int num_joints = 0;              // q's size: the model's joints
  double total_mass = 0.0;         // M_t, kg
  Wrench offset = Wrench::Zero();  // f_0, m_0 (zero without offsets; not added by predict)
  // The recursion's steps and joint lanes, in the SIMD paths' layout (private
  // to the library, which may change it).
  std::shared_ptr<const detail::PredictorPlan> plan;
};

// \param[in] model   the model the parameters were identified for
// \param[in] base    its static base parameters (not base.motion(): InputError)
// \param[in] values  (dim base.num_unknowns()) the base parameters, then the
//                    six offsets when base.offset; another size: ArgumentError
Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values);

// Workspace of predict(), sized once from a predictor (and usable with any
// predictor of the same model).
struct PredictorData {
  explicit PredictorData(const Predictor& predictor);
  // Joint stage, per movable body k (index k - 1), padded to a multiple of 4:
  std::vector<double> sin;  // sin theta_k
  std::vector<double> cos;  // cos theta_k
  // Recursion stage: [4 (n + 1)] sum of c_k + B_k S_k over the children k of
  // body b that are not its first child (zero between calls), padded to 4.
  std::vector<double> gathered;
};

// The mechanism's gravity wrench, WITHOUT the offset f_0, m_0 (what the sensor
// reads and the compensated wrench: IdentifiedModel, identified_model.hpp).
// \param[in] predictor  compiled by compile_predictor (empty: ArgumentError)
// \param[in,out] data   its workspace (made for another model: ArgumentError)
// \param[in] q          (dim predictor.num_joints) joint positions, rad or m
// \param[in] g          (dim 3) gravity in the sensor frame, m/s^2
// A wrong size throws ArgumentError naming the argument (one comparison each).
Wrench predict(const Predictor& predictor, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g);

// Batch form: row i of wrenches from row i of q and of gravity. Does not allocate.
// \param[in] q          (dim N x predictor.num_joints)
// \param[in] gravity    (dim N x 3)
// \param[out] wrenches  (dim N x 6)
// A wrong size throws ArgumentError before anything is written.
void predict(const Predictor& predictor, PredictorData& data,
             const Eigen::Ref<const Eigen::MatrixXd>& q,
             const Eigen::Ref<const Eigen::MatrixXd>& gravity,
             Eigen::Ref<Eigen::MatrixXd> wrenches);

}  // namespace massid

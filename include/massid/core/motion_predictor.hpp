// Real-time prediction of the full wrench in motion (weight and inertial
// forces) from identified dynamic base parameters alone (never from the
// URDF's inertials): the dynamic counterpart of predictor.hpp.
//
// Representatives. A motion base (base_parameters.hpp, ParameterLayout::full)
// is mapped onto standard parameters by its representatives: pi'_c = value of
// the base parameter that stands for column c of Y', every other pi' zero,
// gives the same Y_b pi_b. Back to standard coordinates (M_t = sum_l m_l):
//   m_sensor = M_t - sum_{l != sensor} m_l          (M_t = 0 when total_mass is -1)
//
// Bodies. Links joined by fixed joints are folded into one rigid body b. Its
// frame: where the joint axis is an axis of the parent body's frame, sigma e_m
// (sigma = +-1; most robots), the parent's orientation turned about e_m by a
// constant phi, chosen so that a child's axis is an axis of this frame too;
// else the joint frame turned so that the joint axis is z (C e_z = s). A
// link with parameters (m, h, I_O) and pose (R, t) in its body's frame adds
//   m_b += m,   h_b += R h + m t,
//   I_b += R I_O R^T - ([t][R h] + [R h][t]) + m [t]^T [t]
// (I about the origin, [v] the cross-product matrix; a point mass m at x:
// m [x]^T [x] = m (|x|^2 1 - x x^T)).
//
// Newton-Euler in body frames (bodies numbered depth first, 0 the sensor
// body). Body k with parent p, joint frame (A_k, t_k) in p's frame at q = 0:
//   B_k = A_k Rz(theta_k),   r_k = t_k + d_k A_k e_z                 (general)
//   B_k = R_m(theta_k + phi_k),   r_k = t_k + d_k e_m      (axis sigma e_m of p)
// theta_k = sigma q_k for a revolute joint (else 0), d_k = sigma q_k for a
// prismatic one (else 0); below, z stands for e_m where the axis is e_m. A
// rotation about e_m costs four multiplications, B_k nine. B_k, r_k, sin,
// cos and the joint rates are computed four bodies at a time, off the
// dependent chains.
// Forward pass (w, dw, a: angular velocity, angular acceleration, origin
// acceleration minus gravity, each in its body's frame), seeded with the
// sensor frame's motion: w_0 = omega, dw_0 = omega_dot, a_0 = accel - g:
//   u_k  = a_p + dw_p x r_k + w_p x (w_p x r_k)
//   w_k  = B_k^T w_p + z qd_k                                 (revolute)
//   dw_k = B_k^T dw_p + z qdd_k + (B_k^T w_p) x z qd_k        (revolute)
//   a_k  = B_k^T u_k + z qdd_k + 2 w_k x z qd_k               (prismatic)
// Body wrenches (what body b needs to move as it does, about its origin),
// four bodies at a time (structure of arrays):
//   f_b = m_b a_b + dw_b x h_b + w_b x (w_b x h_b)
//   n_b = I_b dw_b + w_b x (I_b w_b) + h_b x a_b
// Backward pass, k = n .. 1, subtree sums (F, N) = (f, n) to start with:
//   F_p += B_k F_k,   N_p += B_k N_k + r_k x (B_k F_k)
// and the mechanism's wrench on the sensor is -(F_0, N_0) (regressor.hpp:
// this is Y pi for the representatives, the inertia about the link origins).
// Along a serial run the parent's motion and the child's share (F, N) stay in
// registers; only where a branch joins its parent do they go through memory.
//
// MotionPredictor is immutable and compiled once; MotionPredictorData is the
// workspace. No allocation, no branch on the joint type (flags multiply). The
// four-lane path (AVX2, chosen at run time on x86-64) and the two-lane path
// (SSE2 or NEON) do the same operations, with no fused multiply-add, and give
// the same bits; the single and batch forms too.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"

namespace massid {

namespace detail {
struct MotionPredictorPlan;  // the compiled bodies (src/core/motion_predictor_plan.hpp)
}

// A compiled motion predictor: immutable, cheap to copy (copies share the
// plan). Default-constructed it is empty: predict_motion() throws ArgumentError.
struct MotionPredictor {
  int num_joints = 0;              // q's size: the model's joints
  int num_bodies = 1;              // n + 1: the sensor body and one per movable joint
  Wrench offset = Wrench::Zero();  // f_0, m_0 (zero without offsets; not added by predict_motion)
  // The bodies' arrays in the SIMD paths' blocked layout (private to the
  // library, which may change it).
  std::shared_ptr<const detail::MotionPredictorPlan> plan;
};

// \param[in] model   the model the parameters were identified for
// \param[in] base    its dynamic base parameters (base.motion(); else InputError)
// \param[in] values  (dim base.num_unknowns()) the base parameters, then the
//                    six offsets when base.offset; another size: ArgumentError
MotionPredictor compile_motion_predictor(const Model& model, const BaseParameters& base,
                                         const Eigen::Ref<const Eigen::VectorXd>& values);

// Workspace of predict_motion(), sized once from a predictor (and usable with
// any predictor of the same model). Per-body arrays, [lanes x C] with C
// components per body: the bodies padded to a multiple of four, in blocks of
// four bodies with the blocks' components interleaved (component c of body k
// at [4 C (k / 4) + 4 c + k % 4]).
struct MotionPredictorData {
  explicit MotionPredictorData(const MotionPredictor& predictor);
  // Joint stage:
  std::vector<double> sincos;       // [lanes x 2] sin, cos of theta_k + phi_k
  std::vector<double> rotation;     // [lanes x 9] B_k = A_k Rz(theta_k), row-major (general)
  std::vector<double> translation;  // [lanes x 3] r_k = t_k + d_k A_k e_z, parent frame
  // [lanes x 4] sigma (qd_k, qdd_k) of a revolute joint, sigma (2 qd_k, qdd_k) of a prismatic one
  std::vector<double> joint_rates;
  // Forward stage, body frames:
  std::vector<double> motion;  // [lanes x 9] w_k (rad/s), dw_k (rad/s^2), a_k (m/s^2, minus g)
  // Wrench stage: the body wrenches (f_b N, n_b N m about the body origin); the
  // backward stage adds the shares of the children that join at a branch.
  std::vector<double> wrench;  // [lanes x 6]
};

// The mechanism's wrench on the sensor (fx..mz, sensor frame, moment about its
// origin), WITHOUT the offset: weight and motion.
// \param[in] predictor  compiled by compile_motion_predictor (empty: ArgumentError)
// \param[in,out] data   its workspace (made for another model: ArgumentError)
// \param[in] q, qd, qdd (dim predictor.num_joints) joint positions, velocities,
//                       accelerations (rad or m, per s, per s^2); a wrong size
//                       throws ArgumentError
// \param[in] g          (dim 3) gravity in the sensor frame, m/s^2
// \param[in] sensor     the sensor frame's own motion (default: at rest)
Wrench predict_motion(const MotionPredictor& predictor, MotionPredictorData& data,
                      const Eigen::Ref<const Eigen::VectorXd>& q,
                      const Eigen::Ref<const Eigen::VectorXd>& qd,
                      const Eigen::Ref<const Eigen::VectorXd>& qdd, const Eigen::Vector3d& g,
                      const FrameMotion& sensor = {});
// The same from raw arrays (a C caller's, a log's row): q, qd, qdd must each
// hold predictor.num_joints values, which cannot be checked here.
Wrench predict_motion(const MotionPredictor& predictor, MotionPredictorData& data, const double* q,
                      const double* qd, const double* qdd, const Eigen::Vector3d& g,
                      const FrameMotion& sensor = {});

// Batch form, the sensor at rest: row i of wrenches from row i of q, qd, qdd
// and gravity; the same bits as single calls. Does not allocate.
// \param[in] q, qd, qdd  (dim N x predictor.num_joints)
// \param[in] gravity     (dim N x 3)
// \param[out] wrenches   (dim N x 6)
// A wrong size throws ArgumentError before anything is written.
void predict_motion(const MotionPredictor& predictor, MotionPredictorData& data,
                    const Eigen::Ref<const Eigen::MatrixXd>& q,
                    const Eigen::Ref<const Eigen::MatrixXd>& qd,
                    const Eigen::Ref<const Eigen::MatrixXd>& qdd,
                    const Eigen::Ref<const Eigen::MatrixXd>& gravity,
                    Eigen::Ref<Eigen::MatrixXd> wrenches);

// [N x 6] the mechanism's wrench predicted at every sample (weight and
// motion, the sensor's own motion where the samples have it), WITHOUT the
// identified offsets (IdentifiedModel::compensate subtracts them; with level
// data they hold what the offsets absorbed, the weight among it).
Eigen::MatrixXd predict_samples(const MotionPredictor& predictor, MotionPredictorData& data,
                                const Samples& samples);

}  // namespace massid

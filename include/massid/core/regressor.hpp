// The regressor of the standard parameters: the measured wrench is linear in
// them, w = [f; m] = Y pi (parameters.hpp for the layout).
//
// At rest (first-moment layout, 4 per link; paper eqs. 15, 25, 29):
//   f = sum_l m_l g,   m = sum_l (m_l p_l + R_l h_l) x g
//
// In motion (full layout, 10 per link; Raucent et al. 1992, Ayusawa et al.
// 2014): each link's inertial wrench minus its weight, about its origin in its
// frame (w, dw, a from kinematics.hpp, a = origin acceleration - g):
//   f_l = m a + dw x h + w x (w x h)
//   n_l = I dw + w x (I w) + h x a                         (body_regressor)
// and the measured wrench is what the links exert on the sensor:
//   f = - sum_l R_l f_l,   m = - sum_l (R_l n_l + p_l x R_l f_l)
// At rest (a = -g) this is the static form above. Rows of Y: fx, fy, fz, mx,
// my, mz in the sensor frame.
#pragma once

#include <Eigen/Core>
#include <string>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"

namespace massid {

// The first-moment layout's size per link (static code paths).
constexpr int kParamsPerLink = 4;

inline int num_standard_parameters(const Model& model) {
  return kParamsPerLink * model.num_links();
}
// "m", "mx", ..., "izz"
inline const char* standard_parameter_kind(int kind) { return ParameterLayout::kind_name(kind); }
// "mx(link2)" (first-moment layout index)
std::string standard_parameter_name(const Model& model, int index);
// The URDF's inertials as first-moment standard parameters (links without <inertial>: 0).
Eigen::VectorXd nominal_standard_parameters(const Model& model);

// Y: 6 x num_standard_parameters(model), overwritten. `data` must hold the
// forward kinematics of the configuration. (The first-moment layout at rest.)
void standard_regressor(const Model& model, const KinematicsData& data,
                        const Eigen::Vector3d& gravity, Eigen::Ref<Eigen::MatrixXd> Y);

// Body regressor of one link, its frame, about its origin: [f_l; n_l] =
// B(w, dw, a) [m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz].
Eigen::Matrix<double, 6, 10> body_regressor(const Eigen::Vector3d& w, const Eigen::Vector3d& dw,
                                            const Eigen::Vector3d& a);

// One link's block of motion_regressor: its ten parameters' columns
// (m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz about its origin, its frame).
// At rest (forward_kinematics with zero rates) the inertia columns are zero.
Eigen::Matrix<double, 6, 10> link_regressor(const KinematicsData& data, int link);

// Y: 6 x ParameterLayout::full().size(model), overwritten. `data` must hold
// forward_kinematics with motion (velocities, accelerations, gravity).
void motion_regressor(const Model& model, const KinematicsData& data,
                      Eigen::Ref<Eigen::MatrixXd> Y);

}  // namespace massid

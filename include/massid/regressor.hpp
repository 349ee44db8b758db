// The static gravity regressor for the standard parameters:
//
//   w = [f; m] = Y(q, g) pi,   f = sum_l m_l g,
//   m = sum_l (m_l p_l + R_l h_l) x g          (paper eqs. 15, 25, 29)
//
// pi holds four standard parameters per measured link, link-major:
// [m, mx, my, mz] with h_l = (mx, my, mz) = m_l c_l, the first moment in the
// link frame. Rows of Y: fx, fy, fz, mx, my, mz in the sensor frame.
#pragma once

#include <Eigen/Core>
#include <string>

#include "massid/kinematics.hpp"
#include "massid/model.hpp"

namespace massid {

constexpr int kParamsPerLink = 4;
enum StandardParam : int { kMass = 0, kMx = 1, kMy = 2, kMz = 3 };

inline int num_standard_parameters(const Model& model) {
  return kParamsPerLink * model.num_links();
}
// "m", "mx", "my", "mz"
const char* standard_parameter_kind(int param);
// "mx(link2)"
std::string standard_parameter_name(const Model& model, int index);
// The URDF's inertials as standard parameters (links without <inertial>: 0).
Eigen::VectorXd nominal_standard_parameters(const Model& model);

// Y: 6 x num_standard_parameters(model), overwritten. `data` must hold the
// forward kinematics of the configuration.
void standard_regressor(const Model& model, const KinematicsData& data,
                        const Eigen::Vector3d& gravity, Eigen::Ref<Eigen::MatrixXd> Y);

}  // namespace massid

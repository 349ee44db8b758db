#include "massid/core/regressor.hpp"

#include "core/argument_checks.hpp"
#include "core/cross_matrix.hpp"

namespace massid {
namespace {

using detail::skew;

// L(v) with I v = L(v) [ixx, ixy, ixz, iyy, iyz, izz].
Eigen::Matrix<double, 3, 6> inertia_map(const Eigen::Vector3d& v) {
  Eigen::Matrix<double, 3, 6> L;
  L << v.x(), v.y(), v.z(), 0, 0, 0,  //
      0, v.x(), 0, v.y(), v.z(), 0,   //
      0, 0, v.x(), 0, v.y(), v.z();
  return L;
}
}  // namespace

std::string standard_parameter_name(const Model& model, int index) {
  return ParameterLayout::first_moments().name(model, index);
}

Eigen::VectorXd nominal_standard_parameters(const Model& model) {
  return ParameterLayout::first_moments().nominal(model);
}

void standard_regressor(const Model& model, const KinematicsData& data, const Eigen::Vector3d& g,
                        Eigen::Ref<Eigen::MatrixXd> Y) {
  detail::check_size("standard_regressor", "Y rows", Y.rows(), 6, "a wrench");
  detail::check_size("standard_regressor", "Y columns", Y.cols(),
                     kParamsPerLink * model.num_links(), "4 parameters per link");
  detail::check_size("standard_regressor", "data", static_cast<Eigen::Index>(data.rotation.size()),
                     model.num_links(), "a workspace for the model's links");
  Y.setZero();
  for (int l = 0; l < model.num_links(); ++l) {
    const int c = kParamsPerLink * l;
    // mass column: force g, moment p_l x g
    Y.block<3, 1>(0, c + kMass) = g;
    Y.block<3, 1>(3, c + kMass) = data.position[l].cross(g);
    // first-moment columns: moment (R_l e_k) x g
    for (int k = 0; k < 3; ++k) Y.block<3, 1>(3, c + kMx + k) = data.rotation[l].col(k).cross(g);
  }
}

Eigen::Matrix<double, 6, 10> body_regressor(const Eigen::Vector3d& w, const Eigen::Vector3d& dw,
                                            const Eigen::Vector3d& a) {
  Eigen::Matrix<double, 6, 10> B = Eigen::Matrix<double, 6, 10>::Zero();
  const Eigen::Matrix3d W = skew(w);
  B.block<3, 1>(0, kMass) = a;                                    // m a
  B.block<3, 3>(0, kMx) = skew(dw) + W * W;                       // dw x h + w x (w x h)
  B.block<3, 3>(3, kMx) = -skew(a);                               // h x a
  B.block<3, 6>(3, kIxx) = inertia_map(dw) + W * inertia_map(w);  // I dw + w x (I w)
  return B;
}

Eigen::Matrix<double, 6, 10> link_regressor(const KinematicsData& data, int l) {
  const Eigen::Matrix<double, 6, 10> B =
      body_regressor(data.omega[l], data.omega_dot[l], data.accel[l]);
  const Eigen::Matrix3d& R = data.rotation[l];
  // The force f = R B_f is zero in the inertia columns (B's force rows are),
  // and so is its moment p x f: only the first four columns are formed.
  const Eigen::Matrix<double, 3, 4> f = R * B.topLeftCorner<3, 4>();
  Eigen::Matrix<double, 6, 10> Y;
  Y.topLeftCorner<3, 4>() = -f;
  Y.topRightCorner<3, 6>().setZero();
  Y.bottomLeftCorner<3, 4>() = -(R * B.bottomLeftCorner<3, 4>() + skew(data.position[l]) * f);
  Y.bottomRightCorner<3, 6>() = -(R * B.bottomRightCorner<3, 6>());
  return Y;
}

void motion_regressor(const Model& model, const KinematicsData& data,
                      Eigen::Ref<Eigen::MatrixXd> Y) {
  constexpr int P = 10;
  detail::check_size("motion_regressor", "Y rows", Y.rows(), 6, "a wrench");
  detail::check_size("motion_regressor", "Y columns", Y.cols(), P * model.num_links(),
                     "10 parameters per link");
  detail::check_size("motion_regressor", "data", static_cast<Eigen::Index>(data.rotation.size()),
                     model.num_links(), "a workspace for the model's links");
  for (int l = 0; l < model.num_links(); ++l) Y.block<6, P>(0, P * l) = link_regressor(data, l);
}

}  // namespace massid

#include "massid/core/regressor.hpp"

#include "core/argument_checks.hpp"

namespace massid {
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
  // m a; dw x h + w x (w x h) = (skew(dw) + W W) h; h x a = -skew(a) h;
  // I dw + w x (I w) = (L(dw) + W L(w)) [ixx..izz] (I v = L(v) [ixx..izz]),
  // W = skew(w); written out
  // term by term: every entry is a sum of at most two non-zero products, so
  // these are the values the matrix products give.
  const double wx = w.x(), wy = w.y(), wz = w.z(), dx = dw.x(), dy = dw.y(), dz = dw.z();
  Eigen::Matrix<double, 6, 10> B;
  B.col(kMass) << a.x(), a.y(), a.z(), 0.0, 0.0, 0.0;
  B.col(kMx) << -(wz * wz) - wy * wy, dz + wx * wy, -dy + wx * wz, 0.0, -a.z(), a.y();
  B.col(kMx + 1) << -dz + wy * wx, -(wz * wz) - wx * wx, dx + wy * wz, a.z(), 0.0, -a.x();
  B.col(kMx + 2) << dy + wz * wx, -dx + wz * wy, -(wy * wy) - wx * wx, -a.y(), a.x(), 0.0;
  B.col(kIxx) << 0.0, 0.0, 0.0, dx, wz * wx, -(wy * wx);
  B.col(kIxx + 1) << 0.0, 0.0, 0.0, dy + -(wz * wx), dx + wz * wy, -(wy * wy) + wx * wx;
  B.col(kIxx + 2) << 0.0, 0.0, 0.0, dz + wy * wx, wz * wz - wx * wx, dx + -(wy * wz);
  B.col(kIxx + 3) << 0.0, 0.0, 0.0, -(wz * wy), dy, wx * wy;
  B.col(kIxx + 4) << 0.0, 0.0, 0.0, -(wz * wz) + wy * wy, dz + -(wx * wy), dy + wx * wz;
  B.col(kIxx + 5) << 0.0, 0.0, 0.0, wy * wz, -(wx * wz), dz;
  return B;
}

namespace {
// R b, summed as Eigen's 3 x 3 products sum (rows 0 and 1 left to right, row
// 2 from the right): link_regressor's values as they were. Scalars
// throughout: a vector load of values just stored one by one stalls.
inline void rotate(const Eigen::Matrix3d& R, double b0, double b1, double b2, double* out) {
  out[0] = (R(0, 0) * b0 + R(0, 1) * b1) + R(0, 2) * b2;
  out[1] = (R(1, 0) * b0 + R(1, 1) * b1) + R(1, 2) * b2;
  out[2] = R(2, 0) * b0 + (R(2, 1) * b1 + R(2, 2) * b2);
}
}  // namespace

Eigen::Matrix<double, 6, 10> link_regressor(const KinematicsData& data, int l) {
  const Eigen::Matrix<double, 6, 10> B =
      body_regressor(data.omega[l], data.omega_dot[l], data.accel[l]);
  const Eigen::Matrix3d& R = data.rotation[l];
  const double px = data.position[l].x(), py = data.position[l].y(), pz = data.position[l].z();
  // Column by column: the force f = R B_f, zero in the inertia columns (B's
  // force rows are), and the moment R B_n + p x f.
  Eigen::Matrix<double, 6, 10> Y;
  for (int c = 0; c < kIxx; ++c) {
    double f[3], n[3];
    rotate(R, B(0, c), B(1, c), B(2, c), f);
    rotate(R, B(3, c), B(4, c), B(5, c), n);
    Y(0, c) = -f[0];
    Y(1, c) = -f[1];
    Y(2, c) = -f[2];
    Y(3, c) = -(n[0] + (py * f[2] - pz * f[1]));
    Y(4, c) = -(n[1] + (pz * f[0] - px * f[2]));
    Y(5, c) = -(n[2] + (px * f[1] - py * f[0]));
  }
  for (int c = kIxx; c < 10; ++c) {
    double n[3];
    rotate(R, B(3, c), B(4, c), B(5, c), n);
    Y(0, c) = 0.0;
    Y(1, c) = 0.0;
    Y(2, c) = 0.0;
    Y(3, c) = -n[0];
    Y(4, c) = -n[1];
    Y(5, c) = -n[2];
  }
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

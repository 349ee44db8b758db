// The physical quantities of ten standard parameters, without a solver (so
// that reading a params file does not bring in Ceres): the base parameters
// they give, the pseudo-inertia, and one link's mass, centre of mass and
// inertia about it. The fit itself is in physical.cpp.
#include "massid/core/standard_parameters.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace massid {

Eigen::VectorXd base_values_of_standard(const Model& model, const BaseParameters& base,
                                        const Eigen::VectorXd& standard) {
  const int per = base.layout.per_link();
  Eigen::VectorXd pi(base.layout.size(model));
  for (int l = 0; l < model.num_links(); ++l)
    pi.segment(per * l, per) = standard.segment(10 * l, per);
  return base.K * pi;
}

Eigen::Matrix4d pseudo_inertia(const Eigen::Ref<const Eigen::VectorXd>& p) {
  // I from its six entries; Sigma = 1/2 tr(I) 1 - I (Wensing, Kim & Slotine 2017, eq. 8).
  Eigen::Matrix3d I;
  I << p[4], p[5], p[6], p[5], p[7], p[8], p[6], p[8], p[9];
  Eigen::Matrix4d J;
  J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
  J.topRightCorner<3, 1>() = p.segment<3>(1);
  J.bottomLeftCorner<1, 3>() = p.segment<3>(1).transpose();
  J(3, 3) = p[0];
  return J;
}

PhysicalLink physical_link(const std::string& name, const Eigen::Ref<const Eigen::VectorXd>& p) {
  PhysicalLink out;
  out.name = name;
  out.mass = p[0];
  out.com = p[0] != 0.0 ? Eigen::Vector3d(p.segment<3>(1) / p[0]) : Eigen::Vector3d::Zero();
  Eigen::Matrix3d I;
  I << p[4], p[5], p[6], p[5], p[7], p[8], p[6], p[8], p[9];
  // Parallel axes back to the centre of mass: I_C = I_O - m (|c|^2 1 - c c^T).
  out.inertia_com = inertia_about_origin(-out.mass, out.com, I);
  out.principal_moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(out.inertia_com, Eigen::EigenvaluesOnly)
          .eigenvalues();
  const Eigen::Matrix4d J = pseudo_inertia(p);
  out.min_eigenvalue =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J, Eigen::EigenvaluesOnly).eigenvalues()[0];
  // A body, or no body at all (a massless frame: all ten zero, it adds nothing).
  out.consistent =
      (out.mass > 0.0 && out.min_eigenvalue >= -1e-12 * std::abs(J.trace())) || p.isZero(0.0);
  return out;
}

}  // namespace massid

#include "design/design_criterion.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace massid {

CriterionRows::CriterionRows(const Model& model, const BaseParameters& base, Criterion criterion,
                             double noise_force, double noise_moment)
    : model_(model),
      base_(base),
      reg_(model, base),
      criterion_(criterion),
      scale_columns_(criterion == Criterion::Cond && base.motion()) {
  // cond at rest: the moment rows over the moment unknowns, unweighted (eq. 33);
  // otherwise every row over its sigma, every unknown.
  const bool eq36 = criterion_ == Criterion::Cond && !base.motion();
  for (int c = 0; c < base.num_unknowns(); ++c)
    if (!eq36 || base.is_moment_unknown(c)) cols_.push_back(c);
  for (int k = eq36 ? 3 : 0; k < 6; ++k) {
    rows_.push_back(k);
    weight_.push_back(eq36 ? 1.0 : k < 3 ? 1.0 / noise_force : 1.0 / noise_moment);
  }
}

void CriterionRows::weigh(Eigen::Ref<Eigen::MatrixXd> out) const {
  for (int r = 0; r < num_rows(); ++r)
    for (int c = 0; c < size(); ++c) out(r, c) = weight_[r] * reg_.base(rows_[r], cols_[c]);
}

void CriterionRows::rows(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& gravity,
                         Eigen::Ref<Eigen::MatrixXd> out) {
  base_regressor(model_, base_, reg_, q, gravity);
  weigh(out);
}

void CriterionRows::rows(const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Ref<const Eigen::VectorXd>& qd,
                         const Eigen::Ref<const Eigen::VectorXd>& qdd,
                         const Eigen::Vector3d& gravity, const FrameMotion& sensor,
                         Eigen::Ref<Eigen::MatrixXd> out) {
  base_regressor(model_, base_, reg_, q, qd, qdd, gravity, sensor);
  weigh(out);
}

double CriterionRows::value(const Eigen::MatrixXd& info) const {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  if (criterion_ == Criterion::DOpt) {
    Eigen::LLT<Eigen::MatrixXd> llt(info);
    if (llt.info() != Eigen::Success) return kInfinity;
    return -2.0 * llt.matrixLLT().diagonal().array().log().sum();
  }
  Eigen::MatrixXd scaled;
  if (scale_columns_) {
    // D I D with D = diag(I_cc)^-1/2: the information of the regressor with
    // unit-norm columns.
    const Eigen::ArrayXd d = info.diagonal().array().sqrt();
    if (!(d > 0.0).all()) return kInfinity;
    const Eigen::VectorXd inv = d.inverse().matrix();
    scaled = inv.asDiagonal() * info * inv.asDiagonal();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(scale_columns_ ? scaled : info,
                                                    Eigen::EigenvaluesOnly);
  const auto& ev = es.eigenvalues();
  if (!(ev[0] > 1e-13 * ev[ev.size() - 1])) return kInfinity;
  return ev[ev.size() - 1] / ev[0];
}

double CriterionRows::figure(double value) const {
  return criterion_ == Criterion::DOpt ? -value : std::sqrt(value);
}

}  // namespace massid

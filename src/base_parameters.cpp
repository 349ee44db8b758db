#include "massid/base_parameters.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>

#include "massid/kinematics.hpp"
#include "massid/regressor.hpp"
#include "massid/samples.hpp"

namespace massid {
namespace {

// Column j of Y' (the M_t-reparametrised regressor) from the standard one.
void reparametrise(int num_links, const Eigen::Ref<const Eigen::MatrixXd>& Y,
                   Eigen::Ref<Eigen::MatrixXd> Yp) {
  Yp = Y;
  for (int l = 1; l < num_links; ++l) Yp.col(kParamsPerLink * l + kMass) -= Y.col(kMass);
}

// Round-off cleaning: a coefficient within 1e-12 (relative) of a decimal with
// at most 9 significant digits is snapped to it (0.19800000000000003 -> 0.198),
// |c| < 1e-11 becomes 0; anything else (0.7071067811865476) is kept exact.
double clean(double c) {
  if (std::abs(c) < 1e-11) return 0.0;
  const double scale = std::pow(10.0, 8 - std::floor(std::log10(std::abs(c))));
  const double snapped = std::round(c * scale) / scale;
  return std::abs(snapped - c) <= 1e-12 * std::abs(c) ? snapped : c;
}

}  // namespace

std::string BaseParameters::unknown_name(int i) const {
  static const char* const offsets[] = {"offset_fx", "offset_fy", "offset_fz",
                                        "offset_mx", "offset_my", "offset_mz"};
  return i < num_mass() ? params[i].name : offsets[i - num_mass()];
}

bool BaseParameters::is_moment_unknown(int i) const {
  if (i < num_mass()) return i != total_mass;
  return i - num_mass() >= 3;
}

BaseParameters find_base_parameters(const Model& model, const BaseParameterOptions& options) {
  const int L = model.num_links();
  const int n = num_standard_parameters(model);
  const int S = options.samples > 0 ? options.samples : std::max(40, 2 * n);

  // Y' stacked over random configurations and gravity directions.
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, n), Ys(6 * S, n);
  Eigen::VectorXd q(model.num_joints());
  for (int s = 0; s < S; ++s) {
    for (int j = 0; j < model.num_joints(); ++j)
      q[j] = model.joints[j].generic_position(uniform(rng));
    Eigen::Vector3d g(normal(rng), normal(rng), normal(rng));
    g *= kStandardGravity / g.norm();
    forward_kinematics(model, kin, q);
    standard_regressor(model, kin, g, Y);
    reparametrise(L, Y, Ys.middleRows(6 * s, 6));
  }

  // Order of preference: M_t, first moments from the sensor outwards, masses.
  std::vector<int> order{kMass};
  for (int l = 0; l < L; ++l)
    for (int k = kMx; k <= kMz; ++k) order.push_back(kParamsPerLink * l + k);
  for (int l = 1; l < L; ++l) order.push_back(kParamsPerLink * l + kMass);

  // Greedy Gram-Schmidt (twice, for orthogonality) on unit-norm columns.
  std::vector<int> kept, dependent;
  Eigen::MatrixXd Q(6 * S, 0);
  for (int c : order) {
    const double norm = Ys.col(c).norm();
    if (norm == 0.0) {
      dependent.push_back(c);
      continue;
    }
    Eigen::VectorXd r = Ys.col(c) / norm;
    for (int pass = 0; pass < 2; ++pass) r -= Q * (Q.transpose() * r);
    const double rn = r.norm();
    if (rn > options.rank_tolerance) {
      kept.push_back(c);
      Q.conservativeResize(Eigen::NoChange, Q.cols() + 1);
      Q.col(Q.cols() - 1) = r / rn;
    } else {
      dependent.push_back(c);
    }
  }

  // Y'_D = Y'_B beta.
  const int nb = static_cast<int>(kept.size());
  Eigen::MatrixXd YB(6 * S, nb), YD(6 * S, dependent.size());
  for (int i = 0; i < nb; ++i) YB.col(i) = Ys.col(kept[i]);
  for (size_t i = 0; i < dependent.size(); ++i) YD.col(i) = Ys.col(dependent[i]);
  // (No dependent column: nothing to solve; Eigen's solve would bind a
  // reference to the empty matrix's null data.)
  const Eigen::MatrixXd beta =
      YD.cols() > 0 ? Eigen::MatrixXd(YB.colPivHouseholderQr().solve(YD)) : Eigen::MatrixXd(nb, 0);

  // K' in pi' coordinates, then K = K' P with M_t = sum of the masses.
  Eigen::MatrixXd Kp = Eigen::MatrixXd::Zero(nb, n);
  for (int i = 0; i < nb; ++i) {
    Kp(i, kept[i]) = 1.0;
    for (size_t d = 0; d < dependent.size(); ++d) Kp(i, dependent[d]) = clean(beta(i, d));
  }
  Eigen::MatrixXd K = Kp;
  for (int l = 1; l < L; ++l) K.col(kParamsPerLink * l + kMass) += Kp.col(kMass);

  // Names: first moments from the most distal link inwards (p1 = mx of the
  // last link, as in the paper), then moving masses, M last.
  std::vector<int> rank(nb);
  for (int i = 0; i < nb; ++i) rank[i] = i;
  auto key = [&](int i) {
    const int c = kept[i], link = c / kParamsPerLink, k = c % kParamsPerLink;
    if (c == kMass) return std::pair{2, 0};
    if (k == kMass) return std::pair{1, link};
    return std::pair{0, (L - link) * kParamsPerLink + k};
  };
  std::stable_sort(rank.begin(), rank.end(), [&](int a, int b) { return key(a) < key(b); });

  BaseParameters base;
  base.offset = options.offset;
  base.rank_tolerance = options.rank_tolerance;
  base.K.resize(nb, n);
  for (int r = 0; r < nb; ++r) {
    const int i = rank[r];
    const int c = kept[i];
    BaseParameter p;
    p.name = c == kMass ? "M" : "p" + std::to_string(r + 1);
    p.unit = (c % kParamsPerLink == kMass) ? "kg" : "kg m";
    // The representative first, then the other terms in column order.
    p.terms.push_back({c / kParamsPerLink, c % kParamsPerLink, K(i, c)});
    for (int j = 0; j < n; ++j)
      if (j != c && K(i, j) != 0.0)
        p.terms.push_back({j / kParamsPerLink, j % kParamsPerLink, K(i, j)});
    p.expression = format_expression(model, p.terms);
    if (c == kMass) base.total_mass = r;
    base.params.push_back(std::move(p));
    base.K.row(r) = K.row(i);
    base.column.push_back(c);
  }
  return base;
}

}  // namespace massid

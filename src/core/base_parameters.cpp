#include "massid/core/base_parameters.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"

namespace massid {
namespace {

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
  if (i < num_mass()) return motion() || i != total_mass;
  return i - num_mass() >= 3;
}

namespace {

// Y' stacked over the reduction's random configurations (header).
Eigen::MatrixXd random_regressor(const Model& model, const BaseParameterOptions& options, int S) {
  const ParameterLayout& layout = options.layout;
  const int n = layout.size(model), nj = model.num_joints();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, n), Ys(6 * S, n);
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  for (int s = 0; s < S; ++s) {
    for (int j = 0; j < nj; ++j) q[j] = model.joints[j].generic_position(uniform(rng));
    Eigen::Vector3d g(normal(rng), normal(rng), normal(rng));
    g *= kStandardGravity / g.norm();
    if (!layout.inertia()) {
      forward_kinematics(model, kin, q);
      standard_regressor(model, kin, g, Y);
    } else {
      for (int j = 0; j < nj; ++j) {
        qd[j] = 2.0 * normal(rng);
        qdd[j] = 5.0 * normal(rng);
      }
      FrameMotion sensor;
      if (options.sensor_moving)
        for (int k = 0; k < 3; ++k) {
          sensor.omega[k] = normal(rng);
          sensor.omega_dot[k] = 3.0 * normal(rng);
          sensor.accel[k] = 3.0 * normal(rng);
        }
      if (options.fixed_gravity) g = options.sensor_gravity;
      forward_kinematics(model, kin, q, qd, qdd, g, sensor);
      motion_regressor(model, kin, Y);
    }
    // Y'(m_l) = Y(m_l) - Y(m_sensor): the sensor link's mass column stands for M_t.
    auto Yp = Ys.middleRows(6 * s, 6);
    Yp = Y;
    for (int l = 1; l < model.num_links(); ++l) Yp.col(layout.index(l, kMass)) -= Y.col(kMass);
  }
  return Ys;
}

}  // namespace

BaseParameters find_base_parameters(const Model& model, const BaseParameterOptions& options) {
  const ParameterLayout& layout = options.layout;
  const int L = model.num_links();
  const int P = layout.per_link();
  const int n = layout.size(model);
  const int S = options.samples > 0 ? options.samples : std::max(40, 2 * n);
  const Eigen::MatrixXd Ys = random_regressor(model, options, S);

  // Order of preference: M_t, first moments from the sensor outwards, (in
  // motion: then the link's inertia), the other masses.
  std::vector<int> order{kMass};
  for (int l = 0; l < L; ++l)
    for (int k = kMx; k < P; ++k) order.push_back(layout.index(l, k));
  for (int l = 1; l < L; ++l) order.push_back(layout.index(l, kMass));

  // In motion with offsets and a fixed gravity, constant columns are offsets:
  // the offsets' columns come first, and what they span is not identifiable.
  const int rows = static_cast<int>(Ys.rows());
  const bool offsets_first = layout.inertia() && options.offset && options.fixed_gravity;
  const Eigen::MatrixXd O = Eigen::MatrixXd::Identity(6, offsets_first ? 6 : 0).replicate(S, 1);

  // Greedy Gram-Schmidt (twice, for orthogonality) on unit-norm columns; a
  // column whose norm is round-off against the largest is zero (in motion,
  // the columns' scales differ: judged against the largest, not itself).
  double largest = 0.0;
  for (int c = 0; c < n; ++c) largest = std::max(largest, Ys.col(c).norm());
  const double zero = layout.inertia() ? 1e-10 * largest : 0.0;
  std::vector<int> kept, dependent;
  Eigen::MatrixXd Q = O / std::sqrt(static_cast<double>(S));  // the offsets' unit columns
  for (int c : order) {
    const double norm = Ys.col(c).norm();
    if (norm <= zero) {
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

  // Y'_D = [Y'_B O] beta (O's coefficients are what the offsets absorb).
  const int nb = static_cast<int>(kept.size());
  const int no = static_cast<int>(O.cols());
  Eigen::MatrixXd YB(rows, nb + no);
  YB.leftCols(nb) = Ys(Eigen::all, kept);
  YB.rightCols(no) = O;
  const Eigen::MatrixXd YD = Ys(Eigen::all, dependent);
  // (No dependent column: nothing to solve; Eigen's solve would bind a
  // reference to the empty matrix's null data.)
  const Eigen::MatrixXd beta = YD.cols() > 0 ? Eigen::MatrixXd(YB.colPivHouseholderQr().solve(YD))
                                             : Eigen::MatrixXd(nb + no, 0);

  // K' in pi' coordinates, then K = K' P with M_t = sum of the masses.
  Eigen::MatrixXd Kp = Eigen::MatrixXd::Zero(nb, n);
  Kp(Eigen::all, kept).setIdentity();
  Kp(Eigen::all, dependent) = beta.topRows(nb).unaryExpr(&clean);
  Eigen::MatrixXd K = Kp;
  for (int l = 1; l < L; ++l) K.col(layout.index(l, kMass)) += Kp.col(kMass);
  // Coefficients below the rank tolerance relative to the largest of their
  // combination are round-off (the kept columns are only rank_tolerance apart,
  // so beta carries errors up to eps / rank_tolerance): drop them from K, the
  // terms and the expression (ur5_robot.urdf's 1.57079632679 for pi/2 gave
  // "1.95866e-11 ixz(wrist_1_link)" with wrist_1 held, in motion).
  const Eigen::VectorXd cut = options.rank_tolerance * K.rowwise().lpNorm<Eigen::Infinity>();
  K = (K.array().abs() < cut.replicate(1, n).array()).select(0.0, K);

  // Names: first moments (and inertias) from the most distal link inwards (p1
  // = mx of the last link, as in the paper), then moving masses, M last.
  std::vector<int> rank(nb);
  std::iota(rank.begin(), rank.end(), 0);
  auto key = [&](int i) {
    const int c = kept[i], link = layout.link_of(c), k = layout.kind_of(c);
    if (c == kMass) return std::pair{2, 0};
    if (k == kMass) return std::pair{1, link};
    return std::pair{0, (L - link) * P + k};
  };
  std::stable_sort(rank.begin(), rank.end(), [&](int a, int b) { return key(a) < key(b); });

  BaseParameters base;
  base.offset = options.offset;
  base.rank_tolerance = options.rank_tolerance;
  base.layout = layout;
  base.sensor_moving = options.sensor_moving;
  base.fixed_gravity = options.fixed_gravity;
  if (options.fixed_gravity) base.sensor_gravity = options.sensor_gravity;
  base.total_mass = -1;
  base.K.resize(nb, n);
  for (int r = 0; r < nb; ++r) {
    const int i = rank[r];
    const int c = kept[i];
    BaseParameter p;
    p.name = c == kMass ? "M" : "p" + std::to_string(r + 1);
    p.unit = ParameterLayout::kind_unit(layout.kind_of(c));
    // The representative first, then the other terms in column order.
    p.terms.push_back({layout.link_of(c), layout.kind_of(c), K(i, c)});
    for (int j = 0; j < n; ++j)
      if (j != c && K(i, j) != 0.0)
        p.terms.push_back({layout.link_of(j), layout.kind_of(j), K(i, j)});
    p.expression = format_expression(model, p.terms);
    if (c == kMass) base.total_mass = r;
    base.params.push_back(std::move(p));
    base.K.row(r) = K.row(i);
    base.column.push_back(c);
  }
  return base;
}

}  // namespace massid

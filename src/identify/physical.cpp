// fit_physical: the log-Cholesky least-squares problem of physical.hpp, solved
// by Ceres, and parameter_scales (estimation.hpp), whose scales its prior
// shares. Equations: Wensing, Kim & Slotine 2017 (pseudo-inertia),
// Rucker & Wensing 2022 (log-Cholesky parameterisation).
#include "massid/identify/physical.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "core/cross_matrix.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/identify/estimation.hpp"

namespace massid {
namespace {

// PhysicalSummary::converged: a fall of the cost (squared std) that is nothing.
constexpr double kNegligibleCostFall = 1e-8;

using Theta = std::array<double, 10>;

// Ten parameters of a body, m, h and I's ixx, ixy, ixz, iyy, iyz, izz: with
// h = m c and I about the centre of mass the prior's target
// (parameters_of_theta's order), with I about the origin the standard parameters.
Eigen::Matrix<double, 10, 1> ten_parameters(double m, const Eigen::Vector3d& h,
                                            const Eigen::Matrix3d& I) {
  Eigen::Matrix<double, 10, 1> q;
  q << m, h, I(0, 0), I(0, 1), I(0, 2), I(1, 1), I(1, 2), I(2, 2);
  return q;
}

// The scales of parameter_scales and of the prior: the identified total mass
// when positive (else the URDF's) and the robot's reach.
std::pair<double, double> mass_and_reach(const Model& model, const BaseParameters& base,
                                         const IdentifySummary* summary) {
  if (summary && base.total_mass >= 0 && summary->value[base.total_mass] > 0)
    return {summary->value[base.total_mass], reach(model)};
  return {model.nominal_total_mass(), reach(model)};
}

// The ten standard parameters (m, h, inertia about the origin) of a body given
// in frame B, in frame A, with T mapping B coordinates to A (r_A = t + R r_B):
// h_A = m t + R h_B, I_A = R I_B R^T - m [t]^2 - [t][R h_B] - [R h_B][t].
Eigen::Matrix<double, 10, 1> moved_parameters(const Eigen::Matrix<double, 10, 1>& p,
                                              const Eigen::Isometry3d& T) {
  using detail::skew;
  const double m = p[0];
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation(), h = R * p.segment<3>(1);
  Eigen::Matrix3d I;
  I << p[4], p[5], p[6], p[5], p[7], p[8], p[6], p[8], p[9];
  const Eigen::Matrix3d St = skew(t), Sh = skew(h);
  return ten_parameters(m, m * t + h, R * I * R.transpose() - m * St * St - St * Sh - Sh * St);
}

template <class T>
using Matrix4 = Eigen::Matrix<T, 4, 4>;

// The entries (i, j) of U that theta_4 .. theta_9 scale (s12, s23, s13, t1, t2, t3).
constexpr int kShear[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};

// U of the log-Cholesky parameters (physical.hpp), upper triangular 4x4:
//   theta = (alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3)
//   U = e^alpha [[e^d1, s12, s13, t1], [0, e^d2, s23, t2], [0, 0, e^d3, t3], [0, 0, 0, 1]]
template <class T>
Matrix4<T> cholesky_factor(const T* theta) {
  using std::exp;
  const T e = exp(theta[0]);
  Matrix4<T> U = Matrix4<T>::Zero();
  for (int i = 0; i < 3; ++i) U(i, i) = e * exp(theta[1 + i]);
  U(3, 3) = e;
  for (int k = 0; k < 6; ++k) U(kShear[k][0], kShear[k][1]) = e * theta[4 + k];
  return U;
}

// (U U^T)_ij summed over the columns k < columns: J_ij = sum_{k >= max(i,j)}
// U_ik U_jk with columns = 4; with 3, the entries of Ubar Ubar^T (Ubar the
// top-left 3x3 block of U).
template <class T>
T product_entry(const Matrix4<T>& U, int i, int j, int columns) {
  T s = T(0.0);
  for (int k = std::max(i, j); k < columns; ++k) s += U(i, k) * U(j, k);
  return s;
}

// m, h and a rotational inertia of theta: m = J_33, h = J_{0:3,3}, and
//   about the origin (the standard parameters): Sigma = J_{0:3,0:3};
//   about the centre of mass (the prior's coordinates): Sigma_C = Sigma - h h^T / m,
//   the Schur complement of m in J, which for J = U U^T is Ubar Ubar^T;
// the inertia I = tr(S) 1 - S of that S (J's Sigma = 1/2 tr(I) 1 - I inverts to
// I = tr(Sigma) 1 - Sigma) in the order ixx, ixy, ixz, iyy, iyz, izz.
template <class T>
void parameters_of_theta(const T* theta, T* out, bool about_com) {
  const Matrix4<T> U = cholesky_factor(theta);
  out[0] = product_entry(U, 3, 3, 4);
  for (int i = 0; i < 3; ++i) out[1 + i] = product_entry(U, i, 3, 4);
  T S[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S[i][j] = product_entry(U, i, j, about_com ? 3 : 4);
  const T tr = S[0][0] + S[1][1] + S[2][2];
  for (int i = 0, k = 4; i < 3; ++i)
    for (int j = i; j < 3; ++j) out[k++] = i == j ? tr - S[i][j] : -S[i][j];
}

// Prior residuals of one link: weight_k (q_k(theta) - target_k).
struct PriorResidual {
  Eigen::Matrix<double, 10, 1> target, weight;
  template <class T>
  bool operator()(const T* theta, T* r) const {
    T q[10];
    parameters_of_theta(theta, q, true);
    for (int k = 0; k < 10; ++k) r[k] = weight[k] * (q[k] - target[k]);
    return true;
  }
};

// Prior residuals of one link in motion: the log-det (Bregman) divergence of
// its pseudo-inertia from the prior's (Lee, Wensing & Park 2020),
//   d(J || J0) = -log det(J0^-1 J) + tr(J0^-1 J) - 4 >= 0,
// as a sum of squares. With J0 = U0 U0^T and J = U U^T (both U upper
// triangular), V = U0^-1 U is upper triangular and
//   d = sum_i (V_ii^2 - 2 log V_ii - 1) + sum_{i<j} V_ij^2,
// each diagonal term f(x) = e^{2x} - 2x - 1 of x = log V_ii (linear in theta).
// The residuals weight sqrt(2) (sign(x) sqrt(f(x)), V_ij) give the cost
// weight^2 d: relative to each link's own size (a gram on a gripper finger
// weighs like a kilogram on an upper arm), and infinite for a degenerate body.
struct DivergenceResidual {
  Eigen::Matrix4d U0_inverse;  // upper triangular
  double weight = 1.0;
  template <class T>
  bool operator()(const T* theta, T* r) const {
    using std::log;
    using std::sqrt;
    const Matrix4<T> U = cholesky_factor(theta);
    int k = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) {
        T v = T(0.0);  // V_ij = sum_{i <= m <= j} U0^-1_im U_mj
        for (int m = i; m <= j; ++m) v += U0_inverse(i, m) * U(m, j);
        if (i != j) {
          r[k++] = std::sqrt(2.0) * weight * v;
          continue;
        }
        const T x = log(v);
        // sign(x) sqrt(e^{2x} - 2x - 1) = sqrt(2) x sqrt(1 + 2x/3 + x^2/3 + ...), smooth at 0.
        const T f = abs_small(x) ? T(std::sqrt(2.0)) * x * (T(1.0) + x / T(3.0))
                                 : (x < T(0.0) ? T(-1.0) : T(1.0)) *
                                       sqrt(exp(T(2.0) * x) - T(2.0) * x - T(1.0));
        r[k++] = std::sqrt(2.0) * weight * f;
      }
    return true;
  }
  template <class T>
  static bool abs_small(const T& x) {
    return x < T(1e-4) && x > T(-1e-4);
  }
};

// Data residuals: A pi(theta) - b with A = L^-1 K and b = L^-1 pi_b (whitened
// by the covariance of the base parameters), one parameter block of ten per
// link. The Jacobian is A's link columns times d pi_l / d theta_l (forward
// mode, ceres::Jet, per link).
class DataResidual : public ceres::CostFunction {
 public:
  DataResidual(Eigen::MatrixXd A, Eigen::VectorXd b, int num_links, int per_link)
      : A_(std::move(A)), b_(std::move(b)), num_links_(num_links), per_link_(per_link) {
    set_num_residuals(static_cast<int>(b_.size()));
    for (int l = 0; l < num_links; ++l) mutable_parameter_block_sizes()->push_back(10);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    using Jet = ceres::Jet<double, 10>;
    const int nr = num_residuals();
    Eigen::Map<Eigen::VectorXd> r(residuals, nr);
    r = -b_;
    for (int l = 0; l < num_links_; ++l) {
      Jet theta[10], pi[10];
      for (int k = 0; k < 10; ++k) theta[k] = Jet(parameters[l][k], k);
      parameters_of_theta(theta, pi, false);
      Eigen::Matrix<double, 10, 1> value;
      Eigen::Matrix<double, 10, 10> d;  // d pi / d theta
      for (int k = 0; k < 10; ++k) {
        value[k] = pi[k].a;
        d.row(k) = pi[k].v.transpose();
      }
      const auto cols = A_.middleCols(per_link_ * l, per_link_);
      r.noalias() += cols * value.head(per_link_);
      if (jacobians && jacobians[l]) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 10, Eigen::RowMajor>> J(jacobians[l], nr,
                                                                                 10);
        J.noalias() = cols * d.topRows(per_link_);
      }
    }
    return true;
  }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
  int num_links_, per_link_;
};

// The upper-triangular U with J = U U^T (the Cholesky factor taken from the
// other end: P J P = L L^T with P the exchange matrix gives U = P L P), and
// theta from it. J must be positive definite.
Theta theta_of_pseudo_inertia(const Eigen::Matrix4d& J) {
  const Eigen::Matrix4d P = Eigen::Matrix4d::Identity().rowwise().reverse();
  const Eigen::Matrix4d L = (P * J * P).llt().matrixL();
  const Eigen::Matrix4d U = P * L * P;
  const double e = U(3, 3);
  Theta t;
  t[0] = std::log(e);
  for (int i = 0; i < 3; ++i) t[1 + i] = std::log(U(i, i) / e);
  for (int k = 0; k < 6; ++k) t[4 + k] = U(kShear[k][0], kShear[k][1]) / e;
  return t;
}

// The nearest positive-definite J (eigenvalues raised to a floor): where the
// solve starts for a URDF inertial that is not a real body (or a point mass).
Eigen::Matrix4d positive_definite(const Eigen::Matrix4d& J) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(J);
  const double floor = 1e-6 * std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  const Eigen::Vector4d lambda = eig.eigenvalues().cwiseMax(floor);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

Eigen::VectorXd parameter_scales(const Model& model, const BaseParameters& base,
                                 const IdentifySummary* summary) {
  const auto [mass, length] = mass_and_reach(model, base, summary);
  Eigen::VectorXd out(base.num_mass());
  for (int i = 0; i < base.num_mass(); ++i) {
    const std::string& unit = base.params[i].unit;
    const int power = unit == "kg" ? 0 : unit == "kg m" ? 1 : 2;
    out[i] = mass > 0 && length > 0 ? mass * std::pow(length, power)
                                    : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

PhysicalSummary fit_physical(const Model& model, const BaseParameters& base,
                             const IdentifySummary& identified, const PhysicalOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const int nb = base.num_mass(), nl = model.num_links(), per = base.layout.per_link();
  if (identified.value.size() != base.num_unknowns() ||
      identified.covariance.rows() != base.num_unknowns() ||
      identified.covariance.cols() != base.num_unknowns() ||
      base.K.cols() != base.layout.size(model))
    throw InputError(
        fmt::format("physical parameters: the identification has {} unknowns, its base parameters "
                    "{} (not the same model?)",
                    identified.value.size(), base.num_unknowns()));

  // The prior's scales s_k = M L^k (as parameter_scales): the identified
  // total mass (else the URDF's, else 1 kg) and the reach (else 1 m).
  auto [mass, length] = mass_and_reach(model, base, &identified);
  if (!(mass > 0)) mass = 1.0;
  if (!(length > 0)) length = 1.0;
  Eigen::Matrix<double, 10, 1> weight;
  weight << 1.0 / mass, Eigen::Vector3d::Constant(1.0 / (mass * length)),
      Eigen::Matrix<double, 6, 1>::Constant(1.0 / (mass * length * length));
  weight *= options.prior_weight;

  PhysicalSummary out;
  out.static_layout = !base.layout.inertia();
  std::vector<Theta> theta(nl);
  std::vector<bool> prior_body(nl);
  ceres::Problem problem;
  for (int l = 0; l < nl; ++l) {
    const Link& link = model.links[l];
    double m = link.mass;
    Eigen::Vector3d c = link.com;
    Eigen::Matrix3d I = link.inertia;
    prior_body[l] = !link.has_inertial || !(link.mass > 0);
    if (prior_body[l]) {
      // The tiny body: a solid sphere (I = 2/5 m r^2) at the link origin.
      m = options.tiny_mass_fraction * mass;
      c.setZero();
      const double r = options.tiny_radius_fraction * length;
      I = 0.4 * m * r * r * Eigen::Matrix3d::Identity();
    }
    theta[l] = theta_of_pseudo_inertia(
        positive_definite(pseudo_inertia(ten_parameters(m, m * c, inertia_about_origin(m, c, I)))));
    // Bounds (physical.hpp): the mass within [min_mass_fraction,
    // 1/min_mass_fraction] M; each spread e^d, the centre of mass t and the
    // shears s within 1/min_extent_fraction L (spreads at least
    // min_extent_fraction L). Without them an estimate that no body can match
    // (a negative total mass) drives alpha -> -inf (Gauss-Newton steps in
    // log m grow as 1/m) and t, s -> inf, and e^alpha underflows.
    const double far = length / options.min_extent_fraction;
    std::array<std::array<double, 2>, 10> bound;
    for (int k = 0; k < 10; ++k) {
      bound[k][0] = k == 0   ? 0.5 * std::log(options.min_mass_fraction * mass)
                    : k <= 3 ? std::log(options.min_extent_fraction * length)
                             : -far;
      bound[k][1] = k == 0   ? 0.5 * std::log(mass / options.min_mass_fraction)
                    : k <= 3 ? std::log(far)
                             : far;
      theta[l][k] = std::clamp(theta[l][k], bound[k][0], bound[k][1]);
    }
    if (out.static_layout) {  // at rest: each link keeps the URDF's inertia about its centre
      auto* prior = new ceres::AutoDiffCostFunction<PriorResidual, 10, 10>(
          new PriorResidual{ten_parameters(m, m * c, I), weight});
      problem.AddResidualBlock(prior, nullptr, theta[l].data());
    } else {  // in motion: the log-det divergence from the prior body
      const Eigen::Matrix4d U0 = cholesky_factor(theta[l].data());
      auto* prior =
          new ceres::AutoDiffCostFunction<DivergenceResidual, 10, 10>(new DivergenceResidual{
              U0.triangularView<Eigen::Upper>().solve(Eigen::Matrix4d::Identity()),
              options.divergence_weight});
      problem.AddResidualBlock(prior, nullptr, theta[l].data());
    }
    for (int k = 0; k < 10; ++k) {
      problem.SetParameterLowerBound(theta[l].data(), k, bound[k][0]);
      problem.SetParameterUpperBound(theta[l].data(), k, bound[k][1]);
    }
  }

  // Data: whitened by the marginal covariance of the mass base parameters.
  if (nb > 0) {
    Eigen::MatrixXd cov = identified.covariance.topLeftCorner(nb, nb);
    Eigen::LLT<Eigen::MatrixXd> llt(cov);
    // A singular covariance (a parameter given exactly): a tiny ridge.
    for (double ridge = 1e-14; llt.info() != Eigen::Success && ridge < 1; ridge *= 100) {
      Eigen::MatrixXd c2 = cov;
      c2.diagonal() += ridge * cov.diagonal().cwiseAbs().cwiseMax(1e-300);
      llt.compute(c2);
    }
    if (llt.info() != Eigen::Success)
      throw InputError(
          "physical parameters: the covariance of the base parameters is not "
          "positive definite");
    Eigen::MatrixXd A = llt.matrixL().solve(base.K);
    Eigen::VectorXd b = llt.matrixL().solve(identified.value.head(nb));
    std::vector<double*> blocks;
    for (Theta& t : theta) blocks.push_back(t.data());
    problem.AddResidualBlock(new DataResidual(std::move(A), std::move(b), nl, per), nullptr,
                             blocks);
  }

  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  out.standard.resize(10 * nl);
  for (int l = 0; l < nl; ++l) {
    parameters_of_theta(theta[l].data(), out.standard.data() + 10 * l, false);
    out.links.push_back(physical_link(model.links[l].name, out.standard.segment<10>(10 * l)));
    out.links.back().prior_body = prior_body[l];
  }
  // A link the URDF leaves massless, fixed to a neighbour, is a frame the data
  // cannot tell from that neighbour (no wrench separates two rigidly joined
  // bodies): its body joins the neighbour's (the sum of two bodies: consistent,
  // the same wrench) and the frame stays massless. Children first, into their
  // parent; the sensor link into a fixed child with a body.
  const auto merge = [&](int from, int into, const Eigen::Isometry3d& into_from) {
    out.standard.segment<10>(10 * into) +=
        moved_parameters(out.standard.segment<10>(10 * from), into_from);
    out.standard.segment<10>(10 * from).setZero();
    for (const int l : {from, into}) {
      const bool prior = out.links[l].prior_body, unseen = out.links[l].unseen;
      out.links[l] = physical_link(model.links[l].name, out.standard.segment<10>(10 * l));
      out.links[l].prior_body = prior;
      out.links[l].unseen = unseen || l == from;
    }
  };
  for (int l = nl - 1; l >= 1; --l)
    if (prior_body[l] && model.links[l].type == JointType::Fixed)
      merge(l, model.links[l].parent, model.links[l].origin);
  if (nl > 0 && prior_body[0])
    for (int l = 1; l < nl; ++l)
      if (model.links[l].parent == 0 && model.links[l].type == JointType::Fixed &&
          !out.links[l].unseen) {
        merge(0, l, model.links[l].origin.inverse());
        break;
      }
  // The mismatch in std of each base parameter.
  const Eigen::VectorXd fitted = base_values_of_standard(model, base, out.standard);
  out.mismatch.resize(nb);
  for (int i = 0; i < nb; ++i) {
    const double d = fitted[i] - identified.value[i];
    const double s = identified.stddev.size() > i ? identified.stddev[i] : 0.0;
    out.mismatch[i] = s > 0 ? d / s : d == 0 ? 0.0 : std::copysign(INFINITY, d);
    if (out.worst < 0 || std::abs(out.mismatch[i]) > std::abs(out.worst_mismatch)) {
      out.worst = i;
      out.worst_mismatch = out.mismatch[i];
    }
  }
  out.initial_cost = summary.initial_cost;
  out.cost = summary.final_cost;
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 is the start
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  // At the iteration limit, a cost that no longer falls by anything a fit can
  // tell (the data term is in squared std) is converged too: at rest the cost
  // creeps down at 1e-15 for thousands of iterations under Ceres' relative tolerances.
  const std::size_t steps = summary.iterations.size();
  const std::size_t back = std::max<std::size_t>(10, steps / 10);
  if (!out.converged && summary.termination_type == ceres::NO_CONVERGENCE && steps > back)
    out.converged =
        summary.iterations[steps - 1 - back].cost - summary.final_cost < kNegligibleCostFall;
  out.message = summary.message;
  out.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace massid

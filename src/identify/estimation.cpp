#include "massid/identify/estimation.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/argument_checks.hpp"
#include "core/median.hpp"
#include "identify/axis_least_squares.hpp"
#include "identify/chi_square.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

Eigen::MatrixXd stacked_regressor(const Model& model, const BaseParameters& base,
                                  const Samples& samples) {
  RegressorData data(model, base);
  Eigen::MatrixXd A(6 * samples.size(), base.num_unknowns());
  for (int i = 0; i < samples.size(); ++i) {
    base_regressor(model, base, data, samples, i);
    A.middleRows(6 * i, 6) = data.base;  // eq. 33
  }
  return A;
}

double scaled_condition_number(const Eigen::MatrixXd& A) {
  return detail::condition_number(A * detail::column_scale(A).asDiagonal());
}

double moment_condition_number(const BaseParameters& base, const Eigen::MatrixXd& A) {
  const Eigen::Index N = A.rows() / 6;
  return detail::condition_number(
      base, detail::fold_stacked(A, Eigen::VectorXd::Zero(A.rows()), Eigen::VectorXd::Ones(N)));
}

namespace {

using detail::chi_quantile;

// The residuals the outlier test judges, as six numbers per sample whose
// per-axis scales robust_sigma estimates. With gravity taken along the
// measured force (eq. 37, g^ = g0 u, u = f/|f|) each sample's residuals have
// a covariance of their own, derived to first order in the force noise e_f
// (covariance s_f^2 1) and the moment noise e_m (diag(s_m^2)):
//   force:  r_f = f - M g0 u = (|f| - M g0) u: along u, one noise variable
//           a = u^T r_f ~ u^T e_f of variance s_f^2 (the other two axes are
//           zero: 4 degrees of freedom per sample instead of 6);
//   moment: the moment is linear in g, m = J g (J = dm/dg at the fit), and
//           g^ turns with the force noise across it,
//             d g^ = g0 / |f| (1 - u u^T) e_f,
//           so r_m = e_m - J d g^ has covariance
//             C_i = diag(s_m^2) + D_i,  D_i = (g0 s_f / |f_i|)^2 J_i (1 - u_i u_i^T) J_i^T,
//           and no correlation with a ((1 - u u^T) u = 0).
// s_f is the robust scale of a; s_m is estimated below (D_i has rank 2 at
// most: the direction noise moves the moment across the centre of mass only,
// so along it the residual is the moment noise alone, and a per-axis scale
// that ignores this mis-whitens it). Each sample's moment residual is then
// whitened by C_i (z = L_i^-1 r_m, C_i = L_i L_i^T): z has unit covariance,
// and robust_sigma finds its scale near 1.
Eigen::VectorXd outlier_residuals(const Model& model, const BaseParameters& base, const Samples& s,
                                  const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
  if (!s.gravity_from_force || base.motion()) return r;
  const Eigen::Index N = r.size() / 6;
  Eigen::VectorXd out = r;
  std::vector<double> a;
  for (Eigen::Index i = 0; i < N; ++i) {
    const Eigen::Vector3d g = s.gravity.row(i).transpose();
    const double n = g.norm();
    out[6 * i] = n > 0 ? r.segment<3>(6 * i).dot(g) / n : r.segment<3>(6 * i).norm();
    out[6 * i + 1] = out[6 * i + 2] = 0.0;
    a.push_back(std::abs(out[6 * i]));
  }
  if (N < 2) return out;
  const double sf = 1.4826 * detail::median(a);
  // D_i, the direction part of each sample's moment covariance.
  RegressorData data(model, base);
  const int nm = base.num_mass();
  std::vector<Eigen::Matrix3d> D(static_cast<size_t>(N));
  for (Eigen::Index i = 0; i < N; ++i) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) {
      base_regressor(model, base, data, s.q.row(i).transpose(), Eigen::Vector3d::Unit(k));
      J.col(k) = data.base.bottomRows(3).leftCols(nm) * x.head(nm);
    }
    const double f = s.wrench.row(i).head<3>().norm();
    const Eigen::Vector3d u = s.gravity.row(i).transpose().normalized();
    const double k = f > 0 ? kStandardGravity * sf / f : 0.0;
    D[i] = k * k * J * (Eigen::Matrix3d::Identity() - u * u.transpose()) * J.transpose();
  }
  // s_m^2 per axis (V = diag(v)) by maximum likelihood of r_m,i ~ N(0, V + D_i),
  // EM for variance components: with C_i = V + D_i, the moment noise e_m of
  // sample i given r_m,i has E[e e^T | r] = V - V C_i^-1 V + V C_i^-1 r r^T C_i^-1 V,
  // and v_k <- the mean of its diagonal (monotone in the likelihood). Samples
  // whose score is implausible (chi^2 with 3 dof above its 0.999 quantile)
  // are left out of the mean, so that a bump does not inflate the noise.
  Eigen::Vector3d var;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> m;
    for (Eigen::Index i = 0; i < N; ++i) m.push_back(std::abs(r[6 * i + 3 + k]));
    const double total = 1.4826 * detail::median(m);
    var[k] = total * total + 1e-300;
  }
  const Eigen::Vector3d floor = 1e-6 * var;
  const double cut = chi_quantile(0.001, 3);
  for (int it = 0; it < 200; ++it) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double used = 0.0;
    const Eigen::Matrix3d V = var.asDiagonal();
    for (Eigen::Index i = 0; i < N; ++i) {
      const Eigen::Matrix3d Ci = (V + D[i]).inverse();
      const Eigen::Vector3d ri = r.segment<3>(6 * i + 3), c = Ci * ri;
      if (it > 0 && std::sqrt(ri.dot(c)) > cut) continue;
      sum += var - (V * Ci * V).diagonal() + var.cwiseProduct(var).cwiseProduct(c.cwiseProduct(c));
      used += 1.0;
    }
    if (used < 1) break;
    const Eigen::Vector3d next = (sum / used).cwiseMax(floor);
    const bool done = ((next - var).cwiseAbs().array() <= 1e-10 * var.array()).all();
    var = next;
    if (done) break;
  }
  for (Eigen::Index i = 0; i < N; ++i) {
    const Eigen::Matrix3d C = Eigen::Matrix3d(var.asDiagonal()) + D[i];
    out.segment<3>(6 * i + 3) = C.llt().matrixL().solve(r.segment<3>(6 * i + 3));
  }
  return out;
}

// Blocks other than the last sample's, in order of first appearance: per-block
// drift estimates their offsets relative to the last block.
std::vector<int> other_blocks(const Samples& s) {
  std::vector<int> others;
  for (int b : s.block)
    if (b != s.block.back() && std::find(others.begin(), others.end(), b) == others.end())
      others.push_back(b);
  return others;
}

// Drift unknowns: [6N x e] columns beside the base regressor, and their names.
struct DriftColumns {
  Eigen::MatrixXd E;
  std::vector<std::string> names;
};

DriftColumns drift_columns(const Samples& s, Drift drift) {
  const int N = s.size();
  DriftColumns out;
  out.E.resize(6 * N, 0);
  if (drift == Drift::Linear) {
    if (s.time.size() != N)
      throw InputError(s.source + ": a linear drift needs a t column (time of each sample, s)",
                       {{Hint::Setting::Drift, "linear"}});
    const double t_end = s.time.maxCoeff();
    if (!(t_end > s.time.minCoeff()))
      throw IdentifiabilityError(s.source +
                                     ": every sample has the same time t: a drift rate cannot be "
                                     "estimated; record over time, or identify without a drift",
                                 {{Hint::Setting::Drift, "off"}});
    out.E = Eigen::MatrixXd::Zero(6 * N, 6);
    for (int i = 0; i < N; ++i)
      for (int k = 0; k < 6; ++k) out.E(6 * i + k, k) = s.time[i] - t_end;  // offset at t_end
    for (int k = 0; k < 6; ++k)
      out.names.push_back(std::string("drift_") + kWrenchColumns[k] +
                          (k < 3 ? " [N/s]" : " [N m/s]"));
  } else if (drift == Drift::PerBlock) {
    if (static_cast<int>(s.block.size()) != N)
      throw InputError(s.source +
                           ": a drift per block needs a block column (an integer per sample; the "
                           "sensor was re-zeroed between blocks)",
                       {{Hint::Setting::Drift, "per-block"}});
    const int last = s.block.back();
    const std::vector<int> others = other_blocks(s);
    out.E = Eigen::MatrixXd::Zero(6 * N, 6 * others.size());
    for (int i = 0; i < N; ++i) {
      const auto it = std::find(others.begin(), others.end(), s.block[i]);
      if (it == others.end()) continue;
      const int j = static_cast<int>(it - others.begin());
      for (int k = 0; k < 6; ++k) out.E(6 * i + k, 6 * j + k) = 1.0;
    }
    for (int b : others)
      for (int k = 0; k < 6; ++k)
        out.names.push_back(fmt::format("{}[block {}] - {}[block {}] [{}]", kWrenchColumns[k], b,
                                        kWrenchColumns[k], last, k < 3 ? "N" : "N m"));
  }
  return out;
}

// Mean square of the force and of the moment measurements over used samples.
std::array<double, 2> signal_power(const Eigen::VectorXd& y, const Eigen::VectorXd& w) {
  std::array<double, 2> p{0.0, 0.0};
  double used = 0.0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (w[i] <= 0) continue;
    used += 1;
    for (int k = 0; k < 6; ++k) p[k / 3] += y[6 * i + k] * y[6 * i + k] / 3.0;
  }
  for (double& v : p) v /= std::max(used, 1.0);
  return p;
}

// Robust per-axis noise scale: 1.4826 MAD of the residuals of used samples
// (corrected for the degrees of freedom the fit spent on the axis: a residual
// has variance sigma^2 (1 - h), on average 1 - tr(H_kk)/N over the axis),
// floored at 1e-9 of the signal so that round-off in noise-free data never
// looks like an outlier.
Eigen::Matrix<double, 6, 1> robust_sigma(const Eigen::VectorXd& r, const Eigen::VectorXd& w,
                                         const Eigen::VectorXd& y,
                                         const Eigen::Matrix<double, 6, 1>& leverage) {
  const auto power = signal_power(y, w);
  Eigen::Matrix<double, 6, 1> sigma;
  std::vector<double> a;
  for (int k = 0; k < 6; ++k) {
    a.clear();
    for (Eigen::Index i = 0; i < w.size(); ++i)
      if (w[i] > 0) a.push_back(std::abs(r[6 * i + k]));
    const double rows = static_cast<double>(a.size());
    const double dof = std::sqrt(rows / noise_dof(rows, leverage[k]));
    sigma[k] = std::max(1.4826 * detail::median(a) * dof, 1e-9 * std::sqrt(power[k / 3]) + 1e-150);
  }
  return sigma;
}

// Each sample's standardised residual norm d_i.
Eigen::VectorXd scores(const Eigen::VectorXd& r, const Eigen::Matrix<double, 6, 1>& sigma) {
  Eigen::VectorXd d(r.size() / 6);
  for (Eigen::Index i = 0; i < d.size(); ++i)
    d[i] = (r.segment<6>(6 * i).array() / sigma.array()).matrix().norm();
  return d;
}

}  // namespace

double noise_dof(double samples, double leverage) { return std::max(samples - leverage, 0.5); }

// A residual r of sigma 1 exceeds b with probability erfc(b / sqrt 2), the
// chi-square tail of r^2 with one degree of freedom.
double largest_residual_bound(int samples) {
  return chi_quantile(0.01 / (6.0 * std::max(samples, 1)), 1);
}

bool largest_residuals_implausible(const IdentifySummary& s) {
  if (!s.sigma_estimated || s.samples == 0) return false;
  const double bound = largest_residual_bound(s.samples);
  // Gravity along the force (eq. 37): the force residual lies along the force,
  // one noise variable of variance sigma_x^2 + sigma_y^2 + sigma_z^2 whose
  // share per axis varies with the pose; no axis exceeds it.
  const double along = s.sigma.head<3>().norm();
  for (int k = 0; k < 6; ++k)
    if (s.residual_max[k] > bound * (k < 3 && s.gravity_from_force ? along : s.sigma[k]))
      return true;
  return false;
}

IdentifySummary identify(const Model& model, const BaseParameters& base, const Samples& samples,
                         const IdentifyOptions& options) {
  detail::check_samples("identify", model, samples);
  if (!samples.has_wrench())
    throw InputError(samples.source + ": no measured wrench (columns fx,fy,fz,mx,my,mz)");
  // (Excludes the offsets' check in check_unknowns, which needs base.offset.)
  if (options.drift != Drift::None && !base.offset)
    throw InputError(samples.source + ": a drifting offset needs the offsets estimated",
                     {{Hint::Setting::Offset, "on"}});
  const int N = samples.size();
  detail::check_unknowns(samples.source, base, samples.gravity_from_force, N);

  // M = [A E] (6N x q): the base regressor (eq. 33) and the drift columns.
  const int p = base.num_unknowns();
  const DriftColumns drift = drift_columns(samples, options.drift);
  const int e = static_cast<int>(drift.E.cols()), q = p + e;
  Eigen::MatrixXd M = stacked_regressor(model, base, samples);
  if (e > 0) {
    M.conservativeResize(Eigen::NoChange, q);
    M.rightCols(e) = drift.E;
  }
  Eigen::VectorXd y(6 * N);
  for (int i = 0; i < N; ++i) y.segment<6>(6 * i) = samples.wrench.row(i).transpose();
  // Every sample's rows, unweighted: the identifiability check, eq. 36, and
  // the fit when no sample is rejected.
  const detail::AxisFactors all = detail::fold_stacked(M, y, Eigen::VectorXd::Ones(N));
  detail::check_identifiable(model, base, samples, N, all, options.rank_tolerance);
  if (6 * N < q)
    throw IdentifiabilityError(samples.source + ": too few samples for the drift unknowns");

  IdentifySummary out =
      detail::start_summary(N, samples.gravity_from_force, samples.gravity_from_upstream, options);
  out.robust = options.robust;
  out.drift = options.drift;
  const int score_dof = samples.gravity_from_force ? 4 : 6;
  out.outlier_threshold = chi_quantile(options.outlier_probability / N, score_dof);
  out.per_sample_test = true;

  // Weighted least squares over the samples with w_i = 1, the per-axis noise
  // given or re-estimated (detail::fit_noise); x, the residuals y - M x and
  // the leverages per axis of the latest solve.
  Eigen::VectorXd w = Eigen::VectorXd::Ones(N);
  detail::NoiseFit fit = detail::fit_noise(all, q, N, options);
  Eigen::VectorXd x = fit.solution.x, residual = y - M * x;
  detail::Vector6d leverage = fit.solution.leverage;
  if (options.robust) {
    // Robust fit from the least-squares start: Huber weights (a convex
    // problem, 10 steps) then Tukey's biweight with its cut-off at the outlier
    // threshold (redescending: gross errors get weight 0), MAD scales.
    const double huber = chi_quantile(0.1, score_dof), tukey = out.outlier_threshold;
    Eigen::VectorXd x_prev = x;
    for (int it = 0; it < 40; ++it) {
      const Eigen::VectorXd r = outlier_residuals(model, base, samples, x, residual);
      const Eigen::Matrix<double, 6, 1> s = robust_sigma(r, w, y, leverage);
      const Eigen::VectorXd d = scores(r, s);
      for (int i = 0; i < N; ++i) {
        if (it < 10) {
          w[i] = d[i] <= huber ? 1.0 : huber / d[i];
        } else {
          const double u = d[i] / tukey;
          w[i] = u < 1.0 ? (1 - u * u) * (1 - u * u) : 0.0;
        }
      }
      const detail::FactorSolution step =
          detail::solve_factors(detail::fold_stacked(M, y, w), q, s);
      x = step.x;
      leverage = step.leverage;
      residual = y - M * x;
      if (it >= 10 &&
          (x - x_prev).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, x.cwiseAbs().maxCoeff()))
        break;
      x_prev = x;
    }
  }
  // The outlier test on the (robust, or plain) fit's residuals.
  {
    const Eigen::VectorXd every = Eigen::VectorXd::Ones(N);
    const Eigen::VectorXd r = outlier_residuals(model, base, samples, x, residual);
    const Eigen::Matrix<double, 6, 1> s = robust_sigma(r, options.robust ? w : every, y, leverage);
    const Eigen::VectorXd d = scores(r, s);
    for (int i = 0; i < N; ++i)
      if (d[i] > out.outlier_threshold)
        out.outliers.push_back(
            {i, i < static_cast<int>(samples.line.size()) ? samples.line[i] : 0, d[i]});
  }
  if (options.robust) {
    // Rejected samples out, every other in with weight 1: plain weighted
    // least squares, so the covariance and sigma below keep their meaning.
    w.setOnes();
    for (const Outlier& o : out.outliers) w[o.sample] = 0.0;
    if (6 * (N - static_cast<int>(out.outliers.size())) < q)
      throw IdentifiabilityError(samples.source + ": too many samples rejected as outliers");
    fit = out.outliers.empty()
              ? detail::fit_noise(all, q, N, options)
              : detail::fit_noise(detail::fold_stacked(M, y, w), q, w.sum(), options);
    residual = y - M * fit.solution.x;
  }

  if (samples.noise_lags > 0 && base.motion()) {
    // Filtered rows: neighbours' noise correlates (axis_least_squares.hpp).
    detail::LagProducts lags(samples.noise_lags, q);
    detail::LagProducts::Rows rows(q + 1, 6);
    for (int i = 0; i < N; ++i) {
      if (w[i] > 0) {
        rows.topRows(q) = M.middleRows(6 * i, 6).transpose();
        rows.bottomRows<1>() = y.segment<6>(6 * i).transpose();
      } else {
        rows.setZero();  // rejected: its place in the run stays
      }
      lags.add(rows, i < static_cast<int>(samples.block.size()) ? samples.block[i] : 0.0);
    }
    fit.solution.covariance = lags.covariance(fit.solution.covariance, fit.sigma, fit.solution.x,
                                              fit.solution.ssr, w.sum());
  }
  detail::fill_summary(out, fit, p, w.sum());
  out.drift_names = drift.names;
  out.drift_value = fit.solution.x.tail(e);
  out.drift_stddev = fit.solution.covariance.diagonal().tail(e).cwiseSqrt();
  out.residual_max.setZero();
  for (int i = 0; i < N; ++i)
    if (w[i] > 0)
      for (int k = 0; k < 6; ++k)
        out.residual_max[k] = std::max(out.residual_max[k], std::abs(residual[6 * i + k]));
  out.condition_number = detail::condition_number(base, all);
  if (!options.robust && !samples.gravity_from_force && N >= 2) {
    // Rows an external wrench drives, judged as predict judges them.
    const Eigen::MatrixXd R = Eigen::Map<const Eigen::MatrixXd>(residual.data(), 6, N).transpose();
    out.beyond_noise = rows_beyond_noise(samples, R, &out.beyond_noise_threshold);
  }
  return out;
}

Eigen::MatrixXd fitted_wrenches(const Model& model, const BaseParameters& base,
                                const Samples& samples, const IdentifySummary& summary) {
  const int N = samples.size();
  Eigen::MatrixXd W(N, 6);
  RegressorData data(model, base);
  for (int i = 0; i < N; ++i) {
    base_regressor(model, base, data, samples, i);
    W.row(i) = (data.base * summary.value).transpose();  // eq. 29
  }
  if (summary.drift != Drift::None && N > 0) {  // the drift columns' part
    const Eigen::MatrixXd E = drift_columns(samples, summary.drift).E;
    const Eigen::VectorXd drift = E.cols() == summary.drift_value.size()
                                      ? Eigen::VectorXd(E * summary.drift_value)
                                      : Eigen::VectorXd::Zero(6 * N);
    W += Eigen::Map<const Eigen::MatrixXd>(drift.data(), 6, N).transpose();
  }
  return W;
}

}  // namespace massid

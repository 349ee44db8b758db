#include "massid/estimation.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>

#include "massid/base_regressor.hpp"
#include "massid/errors.hpp"
#include "massid/identifiability.hpp"

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

namespace {
// The condition number of M from the small triangular factor of its QR.
double condition_number(const Eigen::MatrixXd& M) {
  if (M.cols() == 0) return 1.0;
  Eigen::MatrixXd R = M;
  if (M.rows() > M.cols()) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
    R = qr.matrixQR().topRows(M.cols()).triangularView<Eigen::Upper>();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R);
  const auto& s = svd.singularValues();
  return s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
}
}  // namespace

double scaled_condition_number(const Eigen::MatrixXd& A) {
  Eigen::VectorXd scale(A.cols());
  for (Eigen::Index c = 0; c < A.cols(); ++c) {
    const double n = A.col(c).norm();
    scale[c] = n > 0 ? 1.0 / n : 1.0;
  }
  return condition_number(A * scale.asDiagonal());
}

double moment_condition_number(const BaseParameters& base, const Eigen::MatrixXd& A) {
  if (base.motion()) return scaled_condition_number(A);
  std::vector<int> cols;
  for (int c = 0; c < base.num_unknowns(); ++c)
    if (base.is_moment_unknown(c)) cols.push_back(c);
  const int N = static_cast<int>(A.rows() / 6);
  Eigen::MatrixXd M(3 * N, cols.size());
  for (int i = 0; i < N; ++i)
    for (size_t k = 0; k < cols.size(); ++k)
      M.block<3, 1>(3 * i, k) = A.block<3, 1>(6 * i + 3, cols[k]);
  return condition_number(M);
}

namespace {

// Chi-square with k (even) degrees of freedom (a sample's k standardised
// residuals): P(X > x) = exp(-x/2) sum_{j < k/2} (x/2)^j / j!; for k = 6,
// exp(-x/2) (1 + x/2 + x^2/8).
double chi2_survival(double x, int k) {
  double term = 1.0, sum = 0.0;
  for (int j = 0; j < k / 2; ++j) {
    sum += term;
    term *= x / 2 / (j + 1);
  }
  return std::exp(-x / 2) * sum;
}

// The score d = sqrt(X) that a clean sample exceeds with probability p.
double chi_quantile(double p, int k) {
  double lo = 0.0, hi = 2000.0;  // survival(2000) underflows to 0
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_survival(mid, k) > p ? lo : hi) = mid;
  }
  return std::sqrt(0.5 * (lo + hi));
}

// The residuals the outlier test judges, as six numbers per sample whose
// per-axis scales robust_sigma estimates. With gravity taken along the
// measured force (eq. 37) a sample's force residual is f - M g0 f/|f|: it
// lies along the force, so its three axes carry one noise variable whose share
// per axis depends on the pose; it is replaced by its component along the
// gravity row (the first force axis; the other two are zero), which leaves 4
// degrees of freedom per sample instead of 6. The moments then carry the
// force's direction noise too: g = g0 f/|f| turns by the force noise across
// it, d g = g0 / |f| (1 - u u^T) d f (u = f/|f|), and the fitted moment moves
// by J d g, J = d m / d g (the moment is linear in g). Each sample's moment
// residual is whitened with C_i = diag(s^2) + (g0 s_f / |f_i|)^2 J_i (1 -
// u u^T) J_i^T, s_f the robust scale of the force residual along the force,
// s^2 the moment noise per axis (the robust residual scale less the median
// direction part).
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
  const auto mad = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return 1.4826 * v[v.size() / 2];
  };
  const double sf = mad(a);
  // Direction part of each sample's moment covariance.
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
  Eigen::Vector3d var;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> m, d;
    for (Eigen::Index i = 0; i < N; ++i) {
      m.push_back(std::abs(r[6 * i + 3 + k]));
      d.push_back(D[i](k, k));
    }
    const double total = mad(m), part = mad(d) / 1.4826;
    var[k] = std::max(total * total - part, 0.01 * total * total) + 1e-300;
  }
  for (Eigen::Index i = 0; i < N; ++i) {
    const Eigen::Matrix3d C = Eigen::Matrix3d(var.asDiagonal()) + D[i];
    const Eigen::Vector3d z = C.llt().matrixL().solve(r.segment<3>(6 * i + 3));
    out.segment<3>(6 * i + 3) = z;
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
      throw InputError(s.source + ": --drift linear needs a t column (time of each sample, s)");
    const double t_end = s.time.maxCoeff();
    if (!(t_end > s.time.minCoeff()))
      throw IdentifiabilityError(s.source +
                                 ": every sample has the same time t: a drift rate cannot be "
                                 "estimated; record over time, or identify without --drift");
    out.E = Eigen::MatrixXd::Zero(6 * N, 6);
    for (int i = 0; i < N; ++i)
      for (int k = 0; k < 6; ++k) out.E(6 * i + k, k) = s.time[i] - t_end;  // offset at t_end
    for (int k = 0; k < 6; ++k)
      out.names.push_back(std::string("drift_") + kWrenchColumns[k] +
                          (k < 3 ? " [N/s]" : " [N m/s]"));
  } else if (drift == Drift::PerBlock) {
    if (static_cast<int>(s.block.size()) != N)
      throw InputError(s.source +
                       ": --drift per-block needs a block column (an integer per sample; the "
                       "sensor was re-zeroed between blocks)");
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

// One weighted least-squares solve of M x = y: rows of sample i weighted by
// sqrt(w_i) / sigma_k (paper eq. 34), columns scaled to unit norm, Householder QR.
struct Solution {
  Eigen::VectorXd x, residual;  // residual = y - M x, unweighted
  Eigen::MatrixXd covariance;   // (M' W M)^-1
  // Per axis k: the trace of the hat matrix over axis k's rows, tr(H_kk), the
  // sum of their leverages: the degrees of freedom the fit spent on axis k
  // (summing to the number of unknowns). E[SSR_k] = sigma_k^2 (N - tr(H_kk)).
  Eigen::Matrix<double, 6, 1> leverage = Eigen::Matrix<double, 6, 1>::Zero();
};

Solution weighted_solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& y,
                        const Eigen::Matrix<double, 6, 1>& sigma, const Eigen::VectorXd& w) {
  const Eigen::Index n = M.cols(), N = w.size();
  Eigen::VectorXd scale(n);
  for (Eigen::Index c = 0; c < n; ++c) scale[c] = 1.0 / M.col(c).norm();
  Eigen::MatrixXd Mw = M * scale.asDiagonal();
  Eigen::VectorXd yw = y;
  for (Eigen::Index i = 0; i < N; ++i)
    for (int k = 0; k < 6; ++k) {
      const double f = std::sqrt(w[i]) / sigma[k];
      Mw.row(6 * i + k) *= f;
      yw[6 * i + k] *= f;
    }
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(Mw);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  const Eigen::VectorXd qty = (qr.householderQ().transpose() * yw).head(n);
  Solution out;
  out.x = scale.asDiagonal() * R.triangularView<Eigen::Upper>().solve(qty);
  const Eigen::MatrixXd Rinv =
      R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(n, n));
  out.covariance = scale.asDiagonal() * (Rinv * Rinv.transpose()) * scale.asDiagonal();
  out.residual = y - M * out.x;
  // Leverage of row r: h_r = |Mw_r R^-1|^2 (the row of the thin Q), summed per
  // axis; a few hundred samples at a time to keep the memory small.
  constexpr Eigen::Index kRows = 6 * 256;
  for (Eigen::Index r0 = 0; r0 < 6 * N; r0 += kRows) {
    const Eigen::Index rows = std::min(kRows, 6 * N - r0);
    const Eigen::MatrixXd Z = Mw.middleRows(r0, rows) * Rinv.triangularView<Eigen::Upper>();
    for (Eigen::Index r = 0; r < rows; ++r) out.leverage[(r0 + r) % 6] += Z.row(r).squaredNorm();
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
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    const double rows = static_cast<double>(a.size());
    const double dof = std::sqrt(rows / noise_dof(rows, leverage[k]));
    sigma[k] = std::max(1.4826 * a[a.size() / 2] * dof, 1e-9 * std::sqrt(power[k / 3]) + 1e-150);
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

double largest_residual_bound(int samples) {
  const double p = 0.01 / (6.0 * std::max(samples, 1));
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return hi;
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
  if (!samples.has_wrench())
    throw InputError(samples.source + ": no measured wrench (columns fx,fy,fz,mx,my,mz)");
  if (base.offset && samples.gravity_from_force)
    throw IdentifiabilityError(
        samples.source +
        ": the sensor offsets cannot be estimated when gravity is taken from the measured force "
        "(no gx,gy,gz columns): a force offset would bend the gravity direction. Add gx,gy,gz "
        "columns, or identify without --offset.");
  if (options.drift != Drift::None && !base.offset)
    throw InputError(samples.source + ": a drifting offset needs the offsets estimated (--offset)");

  const int N = samples.size();
  const int p = base.num_unknowns();
  const Eigen::MatrixXd A = stacked_regressor(model, base, samples);
  Eigen::VectorXd y(6 * N);
  for (int i = 0; i < N; ++i) y.segment<6>(6 * i) = samples.wrench.row(i).transpose();

  if (6 * N < p) {
    throw IdentifiabilityError(samples.source + ": " + std::to_string(N) +
                               " samples give fewer equations than the " + std::to_string(p) +
                               " unknowns; record more poses");
  }
  // M = [A E]: the base regressor (eq. 33) and the drift columns.
  const DriftColumns drift = drift_columns(samples, options.drift);
  const IdentifiabilityReport report =
      check_identifiability(model, base, samples, A, options.rank_tolerance);
  if (!report.ok()) throw IdentifiabilityError(report.message);

  const int e = static_cast<int>(drift.E.cols());
  Eigen::MatrixXd M(6 * N, p + e);
  M.leftCols(p) = A;
  if (e > 0) M.rightCols(e) = drift.E;
  if (6 * N < p + e)
    throw IdentifiabilityError(samples.source + ": too few samples for the drift unknowns");

  IdentifySummary out;
  out.samples = N;
  out.gravity_from_force = samples.gravity_from_force;
  out.gravity_from_upstream = samples.gravity_from_upstream;
  out.sigma_estimated = !options.sigma_force || !options.sigma_moment;
  out.sigma_force_given = options.sigma_force.has_value();
  out.sigma_moment_given = options.sigma_moment.has_value();
  out.robust = options.robust;
  out.drift = options.drift;
  const int score_dof = samples.gravity_from_force ? 4 : 6;
  out.outlier_threshold = chi_quantile(options.outlier_probability / N, score_dof);
  out.per_sample_test = true;

  // Weighted least squares over the samples with w_i = 1, the per-axis noise
  // re-estimated from the residuals (given by the user, else iterated).
  Eigen::Matrix<double, 6, 1> sigma;
  const auto fit = [&](const Eigen::VectorXd& w) {
    for (int k = 0; k < 6; ++k) {
      const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
      sigma[k] = user ? *user : 1.0;  // only the ratio matters for the first solve
    }
    const int iterations = out.sigma_estimated ? std::max(1, options.weight_iterations) : 1;
    const double used = w.sum();
    const auto power = signal_power(y, w);
    Solution sol;
    for (int it = 0; it < iterations; ++it) {
      sol = weighted_solve(M, y, sigma, w);
      if (!out.sigma_estimated) break;
      // sigma_k^2 = SSR_k / (N - tr(H_kk)): each axis' residuals keep N degrees
      // of freedom less those the fit spent on its rows (its leverages), which
      // is unbiased at the right weights. (A force axis' rows involve a few
      // unknowns, a moment axis' most of them: N - n/6 for every axis would
      // understate the moment noise when n approaches 6N.)
      for (int k = 0; k < 6; ++k) {
        const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
        if (user) continue;
        double ssr = 0.0;
        for (int i = 0; i < N; ++i) ssr += w[i] * sol.residual[6 * i + k] * sol.residual[6 * i + k];
        // Floor for noise-free data: round-off relative to the group's signal.
        const double floor = 1e-13 * std::sqrt(power[k / 3]) + 1e-150;
        sigma[k] = std::max(std::sqrt(ssr / noise_dof(used, sol.leverage[k])), floor);
      }
    }
    return sol;
  };

  Eigen::VectorXd w = Eigen::VectorXd::Ones(N);
  Solution sol = fit(w);
  if (options.robust) {
    // Robust fit from the least-squares start: Huber weights (a convex
    // problem, 10 steps) then Tukey's biweight with its cut-off at the outlier
    // threshold (redescending: gross errors get weight 0), MAD scales.
    const double huber = chi_quantile(0.1, score_dof), tukey = out.outlier_threshold;
    Eigen::VectorXd x_prev = sol.x;
    for (int it = 0; it < 40; ++it) {
      const Eigen::VectorXd r = outlier_residuals(model, base, samples, sol.x, sol.residual);
      const Eigen::Matrix<double, 6, 1> s = robust_sigma(r, w, y, sol.leverage);
      const Eigen::VectorXd d = scores(r, s);
      for (int i = 0; i < N; ++i) {
        if (it < 10) {
          w[i] = d[i] <= huber ? 1.0 : huber / d[i];
        } else {
          const double u = d[i] / tukey;
          w[i] = u < 1.0 ? (1 - u * u) * (1 - u * u) : 0.0;
        }
      }
      sol = weighted_solve(M, y, s, w);
      if (it >= 10 && (sol.x - x_prev).cwiseAbs().maxCoeff() <=
                          1e-12 * std::max(1.0, sol.x.cwiseAbs().maxCoeff()))
        break;
      x_prev = sol.x;
    }
  }
  // The outlier test on the (robust, or plain) fit's residuals.
  {
    const Eigen::VectorXd all = Eigen::VectorXd::Ones(N);
    const Eigen::VectorXd r = outlier_residuals(model, base, samples, sol.x, sol.residual);
    const Eigen::Matrix<double, 6, 1> s =
        robust_sigma(r, options.robust ? w : all, y, sol.leverage);
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
    if (6 * (N - static_cast<int>(out.outliers.size())) < p + e)
      throw IdentifiabilityError(samples.source + ": too many samples rejected as outliers");
    sol = fit(w);
  }

  out.value = sol.x.head(p);
  out.sigma = sigma;
  out.covariance = sol.covariance.topLeftCorner(p, p);
  for (int k = 0; k < 6; ++k) out.residual_dof[k] = w.sum() - sol.leverage[k];
  out.stddev = out.covariance.diagonal().cwiseSqrt();
  out.drift_names = drift.names;
  out.drift_value = sol.x.tail(e);
  out.drift_stddev = sol.covariance.diagonal().tail(e).cwiseSqrt();
  double chi2 = 0.0, used = 0.0;
  out.residual_max.setZero();
  out.residual_rms.setZero();
  for (int i = 0; i < N; ++i) {
    if (w[i] <= 0) continue;
    used += 1;
    for (int k = 0; k < 6; ++k) {
      const double r = sol.residual[6 * i + k];
      chi2 += (r / sigma[k]) * (r / sigma[k]);
      out.residual_max[k] = std::max(out.residual_max[k], std::abs(r));
      out.residual_rms[k] += r * r;
    }
  }
  out.residual_rms = (out.residual_rms / std::max(used, 1.0)).cwiseSqrt();
  out.chi2_per_dof = 6 * used > p + e ? chi2 / (6 * used - p - e) : 0.0;
  out.condition_number = moment_condition_number(base, A);
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
  if (summary.drift == Drift::Linear && summary.drift_value.size() == 6) {
    const double t_end = samples.time.maxCoeff();
    for (int i = 0; i < N; ++i)
      W.row(i) += (samples.time[i] - t_end) * summary.drift_value.transpose();
  } else if (summary.drift == Drift::PerBlock && N > 0) {
    const std::vector<int> others = other_blocks(samples);
    for (int i = 0; i < N; ++i) {
      const auto it = std::find(others.begin(), others.end(), samples.block[i]);
      if (it != others.end())
        W.row(i) += summary.drift_value.segment<6>(6 * (it - others.begin())).transpose();
    }
  }
  return W;
}

}  // namespace massid

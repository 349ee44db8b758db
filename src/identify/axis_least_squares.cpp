#include "identify/axis_least_squares.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "massid/core/errors.hpp"
#include "massid/identify/identifiability.hpp"

namespace massid::detail {
Eigen::VectorXd column_scale(const Eigen::MatrixXd& G) {
  return G.colwise().norm().transpose().unaryExpr([](double n) { return n > 0 ? 1.0 / n : 1.0; });
}

double axis_ssr(const AxisFactor& ax, const Eigen::VectorXd& x) {
  const Eigen::Index n = ax.R.rows();
  Eigen::VectorXd xa(n);
  for (Eigen::Index j = 0; j + 1 < n; ++j) xa[j] = x[ax.unknown[j]];
  xa[n - 1] = -1.0;
  return (ax.R.triangularView<Eigen::Upper>() * xa).squaredNorm();
}

Eigen::MatrixXd qr_factor(const Eigen::MatrixXd& M) {
  const Eigen::Index n = M.cols();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(std::max(M.rows(), n), n);
  W.topRows(M.rows()) = M;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
  return qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
}

AxisFactors fold_stacked(const Eigen::MatrixXd& M, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& w) {
  const Eigen::Index N = w.size(), q = M.cols();
  AxisFactors f;
  for (int a = 0; a < 6; ++a) {
    AxisFactor& ax = f[a];
    for (Eigen::Index c = 0; c < q; ++c)
      for (Eigen::Index i = 0; i < N; ++i)
        if (M(6 * i + a, c) != 0.0) {
          ax.unknown.push_back(static_cast<int>(c));
          break;
        }
    const int n = static_cast<int>(ax.unknown.size()) + 1;
    static_cast<FoldedRows&>(ax) = FoldedRows(n, kChunk);
    Eigen::RowVectorXd z(n);
    for (Eigen::Index i = 0; i < N; ++i) {
      if (!(w[i] > 0)) continue;
      const double s = std::sqrt(w[i]);
      for (int c = 0; c + 1 < n; ++c) z[c] = s * M(6 * i + a, ax.unknown[c]);
      z[n - 1] = s * y[6 * i + a];
      ax.add(z);
    }
    ax.flush();
  }
  return f;
}

Eigen::MatrixXd stacked_factors(const AxisFactors& f, int q, bool measured, const Vector6d& sigma,
                                const Eigen::VectorXd& scale) {
  const int extra = measured ? 1 : 0;
  int rows = 0;
  for (const AxisFactor& ax : f) rows += static_cast<int>(ax.unknown.size()) + extra;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(rows, q + extra);
  for (int a = 0, r0 = 0; a < 6; ++a) {
    const AxisFactor& ax = f[a];
    const int n = static_cast<int>(ax.unknown.size());
    for (int i = 0; i < n + extra; ++i) {
      for (int j = i; j < n; ++j) {
        const int c = ax.unknown[j];
        if (c < q)
          G(r0 + i, c) = (scale.size() > 0 ? ax.R(i, j) * scale[c] : ax.R(i, j)) / sigma[a];
      }
      if (measured) G(r0 + i, q) = ax.R(i, n) / sigma[a];
    }
    r0 += n + extra;
  }
  return G;
}

// ---------------------------------------------------------------- checks

void check_unknowns(const std::string& source, const BaseParameters& base, bool gravity_from_force,
                    long long samples) {
  if (base.offset && gravity_from_force)
    throw IdentifiabilityError(
        source +
            ": the sensor offsets cannot be estimated when gravity is taken from the measured "
            "force "
            "(no gx,gy,gz columns): a force offset would bend the gravity direction. Add gx,gy,gz "
            "columns, or identify without the offsets.",
        {{Hint::Setting::Offset, "off"}});
  const int p = base.num_unknowns();
  if (6 * samples < p)
    throw IdentifiabilityError(source + ": " + std::to_string(samples) +
                               " samples give fewer equations than the " + std::to_string(p) +
                               " unknowns; record more poses");
}

void check_identifiable(const Model& model, const BaseParameters& base, const Samples& hints,
                        long long samples, const AxisFactors& f, double rank_tolerance) {
  const IdentifiabilityReport report = check_identifiability(
      model, base, hints, stacked_factors(f, base.num_unknowns()), rank_tolerance);
  if (report.ok()) return;
  std::string message = report.message;
  const std::string said =
      hints.source + ": the " + std::to_string(hints.size()) + " samples determine only";
  if (hints.size() != samples && message.starts_with(said))
    message = hints.source + ": the " + std::to_string(samples) + " samples determine only" +
              message.substr(said.size());
  throw IdentifiabilityError(message, report.hints);
}

// ---------------------------------------------------------------- the solve

FactorSolution solve_factors(const AxisFactors& f, int q, const Vector6d& sigma) {
  const Eigen::VectorXd scale = column_scale(stacked_factors(f, q));
  // The QR of the stacked [R_a S, R_a y] / sigma_a.
  const Eigen::MatrixXd Rw = qr_factor(stacked_factors(f, q, true, sigma, scale));
  const auto Rp = Rw.topLeftCorner(q, q).triangularView<Eigen::Upper>();
  FactorSolution out;
  out.x = scale.asDiagonal() * Rp.solve(Rw.col(q).head(q));
  const Eigen::MatrixXd Rinv = Rp.solve(Eigen::MatrixXd::Identity(q, q));
  out.covariance = scale.asDiagonal() * (Rinv * Rinv.transpose()) * scale.asDiagonal();
  for (int a = 0; a < 6; ++a) {
    const AxisFactor& ax = f[a];
    const int n = static_cast<int>(ax.R.rows());
    out.ssr[a] = axis_ssr(ax, out.x);
    // tr(H_aa) = tr(Mw_a^T Mw_a (Mw^T Mw)^-1) = |R_a S_a Rp^-1|_F^2 / sigma_a^2
    // (Mw_a = M_a S / sigma_a, M_a^T M_a = R_a^T R_a over the axis' columns).
    Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(n - 1, q);
    for (int i = 0; i < n - 1; ++i)
      for (int j = i; j < n - 1; ++j)
        Z.row(i) += (ax.R(i, j) * scale[ax.unknown[j]]) * Rinv.row(ax.unknown[j]);
    out.leverage[a] = Z.squaredNorm() / (sigma[a] * sigma[a]);
  }
  return out;
}

NoiseFit fit_noise(const AxisFactors& f, int q, double used, const IdentifyOptions& options) {
  const bool estimated = !options.sigma_force || !options.sigma_moment;
  NoiseFit out;
  for (int k = 0; k < 6; ++k) {
    const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
    out.sigma[k] = user ? *user : 1.0;  // only the ratio matters for the first solve
  }
  // Mean square of the force and of the moment measurements: |y_a|^2 is the
  // squared norm of R_a's y column.
  double signal[2] = {0.0, 0.0};
  for (int a = 0; a < 6; ++a)
    signal[a / 3] += f[a].R.col(f[a].R.cols() - 1).squaredNorm() / (3.0 * std::max(used, 1.0));
  const int iterations = estimated ? std::max(1, options.weight_iterations) : 1;
  for (int it = 0; it < iterations; ++it) {
    out.solution = solve_factors(f, q, out.sigma);
    if (!estimated) break;
    // sigma_k^2 = SSR_k / (N - tr(H_kk)): each axis' residuals keep N degrees
    // of freedom less those the fit spent on its rows (its leverages), which
    // is unbiased at the right weights. (A force axis' rows involve a few
    // unknowns, a moment axis' most of them: N - q/6 for every axis would
    // understate the moment noise when q approaches 6N.)
    for (int k = 0; k < 6; ++k) {
      const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
      if (user) continue;
      // Floor for noise-free data: round-off relative to the group's signal.
      const double floor = 1e-13 * std::sqrt(signal[k / 3]) + 1e-150;
      out.sigma[k] = std::max(
          std::sqrt(out.solution.ssr[k] / noise_dof(used, out.solution.leverage[k])), floor);
    }
  }
  return out;
}

// ---------------------------------------------------------------- correlated rows

LagProducts::LagProducts(int lags, int q) : lags_(lags), q_(q) {
  G_.assign(6 * static_cast<size_t>(lags), Eigen::MatrixXd::Zero(q + 1, q + 1));
  const FoldedRows empty(q + 1, 16);
  plus_.assign(6 * static_cast<size_t>(lags), empty);
  minus_.assign(6 * static_cast<size_t>(lags), empty);
  pairs_.assign(static_cast<size_t>(lags), 0.0);
}

void LagProducts::pair(const Sample& a, const Sample& b, int lag) {
  pairs_[static_cast<size_t>(lag - 1)] += 1.0;
  for (int k = 0; k < 6; ++k) {
    const size_t at = static_cast<size_t>(k * lags_ + lag - 1);
    G_[at].topLeftCorner(q_, q_).noalias() +=
        a.rows.col(k).head(q_) * b.rows.col(k).head(q_).transpose();
    plus_[at].add((a.rows.col(k) + b.rows.col(k)).transpose());
    minus_[at].add((a.rows.col(k) - b.rows.col(k)).transpose());
  }
}

void LagProducts::add(const Rows& rows, double run) {
  if (!active()) return;
  if (!tail_.empty() && tail_.back().run != run) {
    tail_.clear();
    tail_is_all_ = false;
  }
  Sample s{rows, run};
  const int n = static_cast<int>(tail_.size());
  for (int i = 0; i < n; ++i) pair(tail_[static_cast<size_t>(i)], s, n - i);
  if (static_cast<int>(head_.size()) < lags_) head_.push_back(s);
  tail_.push_back(std::move(s));
  if (static_cast<int>(tail_.size()) > lags_) {
    tail_.erase(tail_.begin());
    tail_is_all_ = false;
  }
  ++count_;
}

void LagProducts::merge(const LagProducts& later) {
  if (!active() || later.count_ == 0) return;
  if (count_ == 0) {
    *this = later;
    return;
  }
  const int L = lags_;
  // This one's last samples (one run) with the later one's first of that run.
  const int n = static_cast<int>(tail_.size());
  for (int j = 0; j < static_cast<int>(later.head_.size()); ++j) {
    if (later.head_[static_cast<size_t>(j)].run != tail_.back().run) break;
    for (int i = 0; i < n; ++i)
      if (n - i + j <= L)
        pair(tail_[static_cast<size_t>(i)], later.head_[static_cast<size_t>(j)], n - i + j);
  }
  LagProducts copy = later;  // (merge flushes its factors)
  for (size_t k = 0; k < G_.size(); ++k) {
    G_[k] += later.G_[k];
    plus_[k].merge(copy.plus_[k]);
    minus_[k].merge(copy.minus_[k]);
  }
  for (int l = 0; l < L; ++l)
    pairs_[static_cast<size_t>(l)] += later.pairs_[static_cast<size_t>(l)];
  for (const Sample& s : later.head_)
    if (static_cast<int>(head_.size()) < L) head_.push_back(s);
  if (later.tail_is_all_ && tail_.back().run == later.tail_.front().run) {
    tail_.insert(tail_.end(), later.tail_.begin(), later.tail_.end());
    if (static_cast<int>(tail_.size()) > L) {
      tail_.erase(tail_.begin(), tail_.end() - L);
      tail_is_all_ = false;
    }
  } else {
    tail_ = later.tail_;
    tail_is_all_ = false;
  }
  count_ += later.count_;
}

Eigen::MatrixXd LagProducts::covariance(const Eigen::MatrixXd& P, const Vector6d& sigma,
                                        const Eigen::VectorXd& x, const Vector6d& ssr,
                                        double used) const {
  if (!active() || used < 2) return P;
  const int L = lags_;
  Eigen::VectorXd v(q_ + 1);
  v << x, -1.0;
  std::vector<FoldedRows> plus = plus_, minus = minus_;
  for (FoldedRows& f : plus) f.flush();
  for (FoldedRows& f : minus) f.flush();
  const auto norm2 = [&](const FoldedRows& f) {
    return (f.R.triangularView<Eigen::Upper>() * v).squaredNorm();
  };
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(q_, q_);
  for (int a = 0; a < 6; ++a) {
    if (!(ssr[a] > 0)) continue;
    std::vector<double> rho(static_cast<size_t>(L), 0.0);
    for (int l = 0; l < L; ++l)
      if (pairs_[static_cast<size_t>(l)] > 0)
        rho[static_cast<size_t>(l)] = 0.25 *
                                      (norm2(plus[static_cast<size_t>(a * L + l)]) -
                                       norm2(minus[static_cast<size_t>(a * L + l)])) /
                                      pairs_[static_cast<size_t>(l)] / (ssr[a] / used);
    // C_a positive semi-definite: its spectrum on a grid, shrunk if negative.
    double worst = 0.0;
    for (int k = 0; k <= 256; ++k) {
      const double w = 3.141592653589793 * k / 256.0;
      double sum = 0.0;
      for (int l = 0; l < L; ++l) sum += 2.0 * rho[static_cast<size_t>(l)] * std::cos(w * (l + 1));
      worst = std::min(worst, sum);
    }
    const double shrink = worst < -1.0 ? -1.0 / worst : 1.0;
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(q_, q_);
    for (int l = 0; l < L; ++l)
      K += shrink * rho[static_cast<size_t>(l)] *
           G_[static_cast<size_t>(a * L + l)].topLeftCorner(q_, q_);
    S += (K + K.transpose()) / (sigma[a] * sigma[a]);
  }
  Eigen::MatrixXd C = P + P * S * P;
  return 0.5 * (C + C.transpose());
}

// ---------------------------------------------------------------- the summary

IdentifySummary start_summary(long long samples, bool gravity_from_force,
                              bool gravity_from_upstream, const IdentifyOptions& options) {
  IdentifySummary out;
  out.samples = static_cast<int>(samples);
  out.gravity_from_force = gravity_from_force;
  out.gravity_from_upstream = gravity_from_upstream;
  out.sigma_estimated = !options.sigma_force || !options.sigma_moment;
  out.sigma_force_given = options.sigma_force.has_value();
  out.sigma_moment_given = options.sigma_moment.has_value();
  return out;
}

void fill_summary(IdentifySummary& out, const NoiseFit& fit, int p, double used) {
  const FactorSolution& s = fit.solution;
  const Eigen::Index q = s.x.size();
  out.value = s.x.head(p);
  out.sigma = fit.sigma;
  out.covariance = s.covariance.topLeftCorner(p, p);
  out.stddev = out.covariance.diagonal().cwiseSqrt();
  double chi2 = 0.0;
  for (int k = 0; k < 6; ++k) {
    out.residual_dof[k] = used - s.leverage[k];
    out.residual_rms[k] = std::sqrt(s.ssr[k] / std::max(used, 1.0));
    chi2 += s.ssr[k] / (fit.sigma[k] * fit.sigma[k]);
  }
  out.chi2_per_dof = 6 * used > q ? chi2 / (6 * used - q) : 0.0;
}

Eigen::JacobiSVD<Eigen::MatrixXd> small_svd(const Eigen::MatrixXd& M, unsigned options) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(M.rows() <= M.cols() ? M : qr_factor(M), options);
}

double condition_number(const Eigen::MatrixXd& M) {
  if (M.cols() == 0) return 1.0;
  const Eigen::VectorXd s = small_svd(M).singularValues();
  return s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
}

double condition_number(const BaseParameters& base, const AxisFactors& f) {
  const int p = base.num_unknowns();
  if (base.motion()) return scaled_condition_number(stacked_factors(f, p));
  // At rest: the moment axes' factors over the moment unknowns, stacked, have
  // the singular values of the stacked moment rows over those unknowns.
  std::vector<int> moment;
  for (int c = 0; c < p; ++c)
    if (base.is_moment_unknown(c)) moment.push_back(c);
  Eigen::Index first = 0;  // the moment axes' first row
  for (int a = 0; a < 3; ++a) first += static_cast<Eigen::Index>(f[a].unknown.size());
  const Eigen::MatrixXd G = stacked_factors(f, p);
  return condition_number(G(Eigen::seq(first, Eigen::last), moment));
}

}  // namespace massid::detail

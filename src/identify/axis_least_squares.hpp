// Private: the one weighted least-squares estimator of identify() and of the
// streamed fit (streaming.hpp), on per-axis triangular factors.
//
// A stacked problem M x ~ y (eq. 33: six rows per sample, fx ... mz, M the
// base regressor and in memory the drift columns beside it) is kept as six
// factors, one per wrench axis a: the triangular factor R_a of that axis' rows
// over the unknowns they involve, with the measurements as the last column,
//   R_a^T R_a = [M_a y_a]^T [M_a y_a].
// R_a is the same for any split or order of the rows (in exact arithmetic),
// so the streamed fit folds its chunks into it (householder_fold.hpp) and the
// in-memory fit folds its stacked rows (fold_stacked). Everything the fit
// reports follows from the six factors: the weighted solve for any per-axis
// noise, the residual sum of squares per axis, the leverages, the
// covariance, the identifiability rank and eq. 36.
//
// Shapes: q unknowns (columns of M); axis a involves n_a - 1 of them
// (AxisFactor::unknown), R_a is n_a x n_a upper triangular; the six stacked
// over the unknowns, G (stacked_factors), is sum_a (n_a - 1) x q with
// G^T G = M^T M. The weighted solve's system is the stacked
// [R_a S / sigma_a | R_a's y column / sigma_a], sum_a n_a x (q + 1), a few
// dozen rows for any number of samples.
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <array>
#include <string>
#include <vector>

#include "identify/householder_fold.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"

namespace massid::detail {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// One wrench axis' rows of the stacked problem, folded (R [n x n]: its last
// column is y's).
struct AxisFactor : FoldedRows {
  std::vector<int> unknown;  // [n - 1] the column of M of each of R's columns but the last
};
using AxisFactors = std::array<AxisFactor, 6>;

// The factors of M x ~ y ([6N x q], [6N]) with sample i's six rows weighted
// by sqrt(w_i) (w [N]; rows with w_i = 0 are left out). Axis a's unknowns are
// the columns with a nonzero entry in its rows (any weight).
AxisFactors fold_stacked(const Eigen::MatrixXd& M, const Eigen::VectorXd& y,
                         const Eigen::VectorXd& w);

// G [sum_a (n_a - 1) x q]: the factors' columns of unknowns below q stacked,
// G^T G = M^T M over those unknowns (same singular values). With `measured`,
// [sum_a n_a x (q + 1)]: every row of each R_a, y's column last. Axis a's
// rows divided by sigma_a, the unknowns' columns multiplied by `scale` (if
// given).
Eigen::MatrixXd stacked_factors(const AxisFactors& f, int q, bool measured = false,
                                const Vector6d& sigma = Vector6d::Ones(),
                                const Eigen::VectorXd& scale = Eigen::VectorXd());

// 1 / the norm of each column of G, 1 for a zero column (column scaling).
Eigen::VectorXd column_scale(const Eigen::MatrixXd& G);

// The residual sum of squares of an axis' rows at x [q] (over every unknown):
// |M_a x - y_a|^2 = |R_a [x_a; -1]|^2.
double axis_ssr(const AxisFactor& ax, const Eigen::VectorXd& x);

// The upper-triangular factor [n x n] of the Householder QR of M [m x n]
// (padded with rows of zeros when m < n).
Eigen::MatrixXd qr_factor(const Eigen::MatrixXd& M);

// ---------------------------------------------------------------- checks

// Before any fit: offsets with gravity from the force (eq. 37), fewer
// equations than unknowns. IdentifiabilityError naming `source`.
void check_unknowns(const std::string& source, const BaseParameters& base, bool gravity_from_force,
                    long long samples);

// The unweighted factors of every sample determine the base parameters
// (check_identifiability on G), else IdentifiabilityError with its message.
// `hints`: the samples the diagnosis re-tests with perturbed poses (all of
// them, or the streamed fit's kept ones: the count in the message is then
// replaced by `samples`).
void check_identifiable(const Model& model, const BaseParameters& base, const Samples& hints,
                        long long samples, const AxisFactors& f, double rank_tolerance);

// ---------------------------------------------------------------- the solve

// One weighted least-squares solve on the factors: axis a's rows divided by
// sigma_a (paper eq. 34), columns scaled to unit norm (S), Householder QR of
// the stacked weighted factors.
struct FactorSolution {
  Eigen::VectorXd x;           // [q]
  Eigen::MatrixXd covariance;  // [q x q] S R^-1 R^-T S = (M^T W M)^-1
  Vector6d ssr;                // per axis, (weighted) residual sum of squares |R_a [x_a; -1]|^2
  // Per axis, tr(H_aa): the fit's leverages summed over the axis' rows (the
  // degrees of freedom it spent there; they sum to q).
  Vector6d leverage;
};
FactorSolution solve_factors(const AxisFactors& f, int q, const Vector6d& sigma);

// The solve with the per-axis noise: given (options.sigma_force,
// sigma_moment), else re-estimated options.weight_iterations times from unit
// weights, sigma_k^2 = SSR_k / noise_dof(used, tr(H_kk)), floored at 1e-13
// of the axis group's rms signal. `used`: the samples in the factors (the sum
// of their 0/1 weights).
struct NoiseFit {
  FactorSolution solution;
  Vector6d sigma;  // the noise per axis the solution is weighted with
};
NoiseFit fit_noise(const AxisFactors& f, int q, double used, const IdentifyOptions& options);

// ---------------------------------------------------------------- correlated rows

// Rows whose noise correlates with their neighbours' (a filtered motion log:
// Samples::noise_lags). Two noises reach a filtered row: the wrench's through
// the smoothing kernel, and the positions' (encoder noise, quantisation)
// through the derivative kernels into the regressor, whose acceleration part
// lies near the cutoff; their mix, hence the rows' correlation, depends on
// the log. It is zero beyond L rows (the filter windows of rows further apart
// share no sample) and across runs. So it is estimated from the residuals,
// per axis a and lag l = 1 .. L (axes taken as independent):
//   rho_al = (sum_i r_i r_{i+l} / n_l) / (SSR_a / N)       (n_l pairs in runs)
// and the weighted least-squares estimate's covariance is the sandwich
//   P (sum_a M_a^T C_a M_a / sigma_a^2) P = P + P (sum_a K_a / sigma_a^2) P,
//   K_a = sum_l rho_al sum_i (m_i m_{i+l}^T + m_{i+l} m_i^T),
// P = (sum_a M_a^T M_a / sigma_a^2)^-1, C_a the correlation matrix of axis
// a's rows (ones on its diagonal, rho_al l rows off it), m_i axis a's row of
// sample i. Both need only the lagged products of the rows augmented with
// their measurement, z_i = [m_i; y_i]: G_al = sum_i z_i z_{i+l}^T gives
// sum_i r_i r_{i+l} = [x; -1]^T G_al [x; -1] once x is known, and K_a from
// its leading block, so one pass suffices. That sum would cancel (y against
// its residual), so it is taken from the triangular factors T+-_al of the
// rows z_i +- z_{i+l} instead, as a residual sum of squares is:
//   sum_i r_i r_{i+l} = (|T+_al v|^2 - |T-_al v|^2) / 4,  v = [x; -1].
// Only G_al's leading block is used. LagProducts accumulates G_al a
// sample at a time in order, keeping the last L samples; merge() appends a
// later partial (its first L samples pair with this one's last), so a stream
// split into blocks gives the in-memory sums. (If the estimated rho_al would
// make C_a indefinite, they are shrunk until its spectrum
// 1 + 2 sum_l rho_al cos(w l) is non-negative.)
class LagProducts {
 public:
  // [(q + 1) x 6]: column a, axis a's row over the q unknowns, then y_a.
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, 6>;
  LagProducts() = default;  // independent rows: nothing accumulated
  LagProducts(int lags, int q);
  bool active() const { return lags_ > 0; }
  LagProducts empty_like() const { return active() ? LagProducts(lags_, q_) : LagProducts(); }
  // The next sample's rows; consecutive samples with equal `run` are one run.
  void add(const Rows& rows, double run);
  void merge(const LagProducts& later);
  // The sandwich for the solution x [q] with per-axis residual sums of
  // squares ssr over `used` samples, weighted by sigma (P itself when
  // inactive).
  Eigen::MatrixXd covariance(const Eigen::MatrixXd& P, const Vector6d& sigma,
                             const Eigen::VectorXd& x, const Vector6d& ssr, double used) const;

 private:
  struct Sample {
    Rows rows;
    double run = 0.0;
  };
  void pair(const Sample& a, const Sample& b, int lag);
  int lags_ = 0, q_ = 0;
  std::vector<Eigen::MatrixXd> G_;        // [6 L]: axis a, lag l at a L + l - 1
  std::vector<FoldedRows> plus_, minus_;  // [6 L]: T+-_al
  std::vector<double> pairs_;             // [L]
  std::vector<Sample> head_;              // the first L samples
  std::vector<Sample> tail_;              // the last L samples of the current run, in order
  long long count_ = 0;
  bool tail_is_all_ = true;  // tail_ holds every sample added (one run)
};

// ---------------------------------------------------------------- the summary

// What every fit reports of its data and options (samples, where gravity came
// from, which sigma were given).
IdentifySummary start_summary(long long samples, bool gravity_from_force,
                              bool gravity_from_upstream, const IdentifyOptions& options);
// The fit's part for the first p unknowns (the base parameters and offsets):
// value, covariance, stddev, sigma, residual_dof, residual_rms and
// chi2_per_dof (over 6 used - q degrees of freedom). residual_max is left to
// the caller (it needs the rows).
void fill_summary(IdentifySummary& out, const NoiseFit& fit, int p, double used);

// eq. 36 from the unweighted factors: at rest the stacked moment axes over
// the moment unknowns, unscaled; in motion every unknown below base's count,
// columns scaled (as moment_condition_number of the stacked regressor).
double condition_number(const BaseParameters& base, const AxisFactors& f);
// The condition number of a matrix, from the triangular factor of its QR.
double condition_number(const Eigen::MatrixXd& M);
// The SVD of M (`options`: Eigen::ComputeFullV for its right singular
// vectors) from the triangular factor of its QR when M has more rows than
// columns (the same singular values and right singular vectors).
Eigen::JacobiSVD<Eigen::MatrixXd> small_svd(const Eigen::MatrixXd& M, unsigned options = 0);

}  // namespace massid::detail

#include "massid/estimation.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
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
    base_regressor(model, base, data, samples.q.row(i).transpose(),
                   samples.gravity.row(i).transpose());
    A.middleRows(6 * i, 6) = data.base;  // eq. 33
  }
  return A;
}

double moment_condition_number(const BaseParameters& base, const Eigen::MatrixXd& A) {
  std::vector<int> cols;
  for (int c = 0; c < base.num_unknowns(); ++c)
    if (base.is_moment_unknown(c)) cols.push_back(c);
  const int N = static_cast<int>(A.rows() / 6);
  Eigen::MatrixXd M(3 * N, cols.size());
  for (int i = 0; i < N; ++i)
    for (size_t k = 0; k < cols.size(); ++k)
      M.block<3, 1>(3 * i, k) = A.block<3, 1>(6 * i + 3, cols[k]);
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
  const IdentifiabilityReport report =
      check_identifiability(model, base, samples, A, options.rank_tolerance);
  if (!report.ok()) throw IdentifiabilityError(report.message);

  IdentifySummary out;
  out.samples = N;
  out.gravity_from_force = samples.gravity_from_force;
  out.sigma_estimated = !options.sigma_force || !options.sigma_moment;

  // Column scaling for a well-conditioned QR; x = S x_s.
  Eigen::VectorXd scale(p);
  for (int c = 0; c < p; ++c) scale[c] = 1.0 / A.col(c).norm();

  // Initial per-axis sigma: the user's, else the RMS of the measurement per
  // axis group (only the ratio matters for the first solve).
  Eigen::Matrix<double, 6, 1> sigma;
  for (int k = 0; k < 6; ++k) {
    const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
    sigma[k] = user ? *user : 1.0;
  }
  const int iterations = out.sigma_estimated ? std::max(1, options.weight_iterations) : 1;
  Eigen::VectorXd x(p), residual(6 * N);
  Eigen::MatrixXd Rinv;
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd Aw = A * scale.asDiagonal();
    Eigen::VectorXd yw = y;
    for (int i = 0; i < N; ++i)
      for (int k = 0; k < 6; ++k) {
        Aw.row(6 * i + k) /= sigma[k];
        yw[6 * i + k] /= sigma[k];
      }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(Aw);
    const Eigen::MatrixXd R = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
    const Eigen::VectorXd qty = (qr.householderQ().transpose() * yw).head(p);
    const Eigen::VectorXd xs = R.triangularView<Eigen::Upper>().solve(qty);
    x = scale.asDiagonal() * xs;
    Rinv = R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
    residual = y - A * x;
    if (!out.sigma_estimated) break;
    // sigma_k^2 = SSR_k / (N - p/6): the 6N - p degrees of freedom shared over the axes.
    const double dof = std::max(1.0, N - p / 6.0);
    double signal[2] = {0.0, 0.0};  // mean square of the force and moment measurements
    for (int i = 0; i < 6 * N; ++i) signal[(i % 6) / 3] += y[i] * y[i] / (3.0 * N);
    for (int k = 0; k < 6; ++k) {
      const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
      if (user) continue;
      double ssr = 0.0;
      for (int i = 0; i < N; ++i) ssr += residual[6 * i + k] * residual[6 * i + k];
      // Floor for noise-free data: round-off relative to the group's signal.
      const double floor = 1e-13 * std::sqrt(signal[k / 3]) + 1e-150;
      sigma[k] = std::max(std::sqrt(ssr / dof), floor);
    }
  }

  out.value = x;
  out.sigma = sigma;
  out.covariance = scale.asDiagonal() * (Rinv * Rinv.transpose()) * scale.asDiagonal();
  out.stddev = out.covariance.diagonal().cwiseSqrt();
  double chi2 = 0.0;
  out.residual_max.setZero();
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < 6; ++k) {
      const double r = residual[6 * i + k];
      chi2 += (r / sigma[k]) * (r / sigma[k]);
      out.residual_max[k] = std::max(out.residual_max[k], std::abs(r));
    }
  for (int k = 0; k < 6; ++k) {
    double ssr = 0.0;
    for (int i = 0; i < N; ++i) ssr += residual[6 * i + k] * residual[6 * i + k];
    out.residual_rms[k] = std::sqrt(ssr / N);
  }
  out.chi2_per_dof = 6 * N > p ? chi2 / (6 * N - p) : 0.0;
  out.condition_number = moment_condition_number(base, A);
  return out;
}

}  // namespace massid

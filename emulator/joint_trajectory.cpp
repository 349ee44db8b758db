#include "massid/emulator/joint_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "massid/core/errors.hpp"

namespace massid::emulator {

JointTrajectory smooth_maneuver(const Model& model, double duration) {
  const int n = model.num_joints();
  Eigen::VectorXd mid(n), amp(n);
  for (int j = 0; j < n; ++j) {
    const Joint& joint = model.joints[j];
    const double lo = joint.limited ? joint.lower : joint.generic_position(0.0);
    const double hi = joint.limited ? joint.upper : joint.generic_position(1.0);
    mid[j] = 0.5 * (lo + hi);
    const double a = joint.type == JointType::Prismatic ? 0.25 * (hi - lo) : 1.2;
    amp[j] = std::min(a, 0.45 * (hi - lo));
  }
  return [mid, amp, duration](double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                              Eigen::VectorXd& qdd) {
    // sin^2(w t) = (1 - cos(2 w t)) / 2
    const double w = std::numbers::pi / duration;
    const double u = std::clamp(t, 0.0, duration);
    const double moving = t > 0.0 && t < duration ? 1.0 : 0.0;
    q = mid + amp * (0.5 - 0.5 * std::cos(2 * w * u));
    qd = amp * (moving * w * std::sin(2 * w * u));
    qdd = amp * (moving * 2 * w * w * std::cos(2 * w * u));
  };
}

JointTrajectory spline_trajectory(const Eigen::VectorXd& t, const Eigen::MatrixXd& q) {
  const Eigen::Index n = t.size();
  if (n == 0 || q.rows() != n) throw InputError("spline_trajectory: no samples, or t and q differ");
  for (Eigen::Index k = 1; k < n; ++k)
    if (!(t[k] > t[k - 1])) throw InputError("spline_trajectory: times must increase");
  // Second derivatives m at the knots (one row per knot), clamped ends q' = 0:
  // a tridiagonal system solved by the Thomas algorithm for all joints at once.
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, q.cols());
  if (n > 1) {
    Eigen::VectorXd diag(n), upper(n);
    Eigen::MatrixXd rhs(n, q.cols());
    const auto h = [&t](Eigen::Index k) { return t[k + 1] - t[k]; };
    const auto slope = [&](Eigen::Index k) { return (q.row(k + 1) - q.row(k)) / h(k); };
    diag[0] = 2 * h(0);
    upper[0] = h(0);
    rhs.row(0) = 6 * slope(0);
    for (Eigen::Index k = 1; k + 1 < n; ++k) {
      diag[k] = 2 * (h(k - 1) + h(k));
      upper[k] = h(k);
      rhs.row(k) = 6 * (slope(k) - slope(k - 1));
    }
    diag[n - 1] = 2 * h(n - 2);
    upper[n - 1] = 0.0;
    rhs.row(n - 1) = -6 * slope(n - 2);
    // Forward elimination (the sub-diagonal of row k is h(k-1)), back substitution.
    for (Eigen::Index k = 1; k < n; ++k) {
      const double f = h(k - 1) / diag[k - 1];
      diag[k] -= f * upper[k - 1];
      rhs.row(k) -= f * rhs.row(k - 1);
    }
    m.row(n - 1) = rhs.row(n - 1) / diag[n - 1];
    for (Eigen::Index k = n - 2; k >= 0; --k)
      m.row(k) = (rhs.row(k) - upper[k] * m.row(k + 1)) / diag[k];
  }
  return [t, q, m](double time, Eigen::VectorXd& out, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) {
    const Eigen::Index n = t.size();
    if (n == 1 || time <= t[0] || time >= t[n - 1]) {
      out = q.row(time >= t[n - 1] ? n - 1 : 0).transpose();
      qd.setZero(q.cols());
      qdd.setZero(q.cols());
      return;
    }
    const Eigen::Index k = std::upper_bound(t.data(), t.data() + n, time) - t.data() - 1;
    const double h = t[k + 1] - t[k], a = t[k + 1] - time, b = time - t[k];
    const auto c0 = (q.row(k) / h - m.row(k) * (h / 6)).transpose();
    const auto c1 = (q.row(k + 1) / h - m.row(k + 1) * (h / 6)).transpose();
    out = m.row(k).transpose() * (a * a * a / (6 * h)) +
          m.row(k + 1).transpose() * (b * b * b / (6 * h)) + c0 * a + c1 * b;
    qd = -m.row(k).transpose() * (a * a / (2 * h)) + m.row(k + 1).transpose() * (b * b / (2 * h)) -
         c0 + c1;
    qdd = m.row(k).transpose() * (a / h) + m.row(k + 1).transpose() * (b / h);
  };
}

}  // namespace massid::emulator

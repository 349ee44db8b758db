#include "massid/identify/rest_windows.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/median.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/regressor.hpp"

namespace massid {

namespace {

using detail::median;

// The sample period: the median step of t (at least two rows).
double median_step(const Eigen::VectorXd& t) {
  const Eigen::VectorXd steps = t.tail(t.size() - 1) - t.head(t.size() - 1);
  return median(std::vector<double>(steps.begin(), steps.end()));
}

// 8 sigma of a signal's noise from its steps (motion is rare among them), at least `floor`.
double tolerance(const Eigen::Ref<const Eigen::VectorXd>& x, double floor) {
  std::vector<double> steps;
  steps.reserve(static_cast<std::size_t>(std::max<Eigen::Index>(x.size() - 1, 0)));
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) steps.push_back(std::abs(x[i + 1] - x[i]));
  return std::max(8.0 * 1.4826 * median(std::move(steps)) / std::sqrt(2.0), floor);
}

// Marks the rows of x that differ by more than tol from the rows k before and k after.
int mark(const Eigen::Ref<const Eigen::VectorXd>& x, int k, double tol, std::vector<char>& moving) {
  int marked = 0;
  const int n = static_cast<int>(x.size());
  for (int i = k; i + k < n; ++i)
    if (std::abs(x[i] - x[i - k]) > tol && std::abs(x[i + k] - x[i]) > tol && !moving[i]) {
      moving[i] = 1;
      ++marked;
    }
  return marked;
}

// The settling check (rest_windows.hpp): blocks of `len` rows from the
// window's start (and from its end) against the statistics of the blocks of
// the windows' second halves, pooled over the windows, per wrench channel.
struct Reference {
  std::vector<Eigen::Matrix<double, 6, 1>> level;  // per window: median of its second half
  Eigen::Matrix<double, 6, 1> mean_scale, energy_median, energy_scale;
  bool ok = false;
};

// Mean deviation from `level` and mean square deviation of rows [r, r + len).
void block_stats(const Eigen::MatrixXd& wrench, int r, int len,
                 const Eigen::Matrix<double, 6, 1>& level, Eigen::Matrix<double, 6, 1>& mean,
                 Eigen::Matrix<double, 6, 1>& energy) {
  const Eigen::MatrixXd d = wrench.middleRows(r, len).rowwise() - level.transpose();
  mean = d.colwise().sum().transpose() / len;
  energy = d.cwiseAbs2().colwise().sum().transpose() / len;
}

Reference reference(const Eigen::MatrixXd& wrench, const std::vector<RestWindow>& windows,
                    int len) {
  Reference ref;
  std::vector<std::vector<double>> means(6), energies(6);
  for (const RestWindow& w : windows) {
    const int mid = (w.first + w.last + 1) / 2;
    Eigen::Matrix<double, 6, 1> level;
    for (int c = 0; c < 6; ++c) {
      const auto half = wrench.col(c).segment(mid, w.last - mid + 1);
      level[c] = median(std::vector<double>(half.begin(), half.end()));
    }
    ref.level.push_back(level);
    Eigen::Matrix<double, 6, 1> m, e;
    for (int r = mid; r + len - 1 <= w.last; r += len) {
      block_stats(wrench, r, len, level, m, e);
      for (int c = 0; c < 6; ++c) {
        means[c].push_back(std::abs(m[c]));
        energies[c].push_back(e[c]);
      }
    }
  }
  if (means[0].size() < 8) return ref;
  for (int c = 0; c < 6; ++c) {
    ref.mean_scale[c] = 1.4826 * median(means[c]);
    ref.energy_median[c] = median(energies[c]);
    std::vector<double> spread;
    for (double e : energies[c]) spread.push_back(std::abs(e - ref.energy_median[c]));
    ref.energy_scale[c] = 1.4826 * median(std::move(spread));
  }
  ref.ok = (ref.mean_scale.array() > 0).all() && (ref.energy_scale.array() > 0).all();
  return ref;
}

// A block still settling: its mean or its mean square deviation from the
// window's level is beyond what the reference blocks show (4.5 and 6 of their
// robust scales: a block of noise goes beyond about once in 10^5).
bool unsettled(const Eigen::MatrixXd& wrench, int r, int len, const Reference& ref, int window) {
  Eigen::Matrix<double, 6, 1> m, e;
  block_stats(wrench, r, len, ref.level[window], m, e);
  return (m.cwiseAbs().array() > 4.5 * ref.mean_scale.array()).any() ||
         (e.array() > ref.energy_median.array() + 6.0 * ref.energy_scale.array()).any();
}

// Trims each window where the wrench has not settled: at its start, up to
// the last unsettled block in its first half; at its end, the unsettled
// blocks before the next motion. Blocks of `base` rows and of 8 times that.
void trim_settling(const Eigen::MatrixXd& wrench, int base, int shortest, RestWindows& out,
                   double dt) {
  std::vector<RestWindow> trimmed = out.windows;
  for (int len : {base, 8 * base}) {
    const Reference ref = reference(wrench, out.windows, len);
    if (!ref.ok) continue;
    for (std::size_t k = 0; k < out.windows.size(); ++k) {
      const RestWindow& w = out.windows[k];
      const int mid = (w.first + w.last + 1) / 2;
      if (w.last - mid + 1 < 2 * len) continue;  // too short to judge at this scale
      for (int r = w.first; r + len <= mid; r += len)
        if (unsettled(wrench, r, len, ref, static_cast<int>(k)))
          trimmed[k].first = std::max(trimmed[k].first, r + len);
      for (int r = w.last - len + 1;
           r >= mid && unsettled(wrench, r, len, ref, static_cast<int>(k)); r -= len)
        trimmed[k].last = std::min(trimmed[k].last, r - 1);
    }
  }
  std::vector<RestWindow> kept;
  out.samples = 0;
  for (std::size_t k = 0; k < trimmed.size(); ++k) {
    const RestWindow& w = trimmed[k];
    const int before = out.windows[k].last - out.windows[k].first + 1;
    const int after = std::max(0, w.last - w.first + 1);
    const int start = std::max(0, w.first - out.windows[k].first);
    out.longest_settling = std::max(out.longest_settling, start * dt);
    if (after >= shortest) {
      kept.push_back(w);
      out.samples += after;
      out.trimmed += before - after;
    } else {
      out.trimmed += before;
    }
  }
  out.windows = std::move(kept);
}

RestWindows every_row(int n) {
  RestWindows w;
  w.rows = w.samples = n;
  if (n > 0) w.windows.push_back({0, n - 1});
  return w;
}

}  // namespace

RestWindows find_rest_windows(const Samples& s, const RestWindowOptions& o) {
  const int n = s.size();
  if (o.detection == RestDetection::Off || s.time.size() != n || n < 3) return every_row(n);
  const double dt = median_step(s.time);
  if (!(dt > 0.0) || dt > o.max_step) return every_row(n);
  const int k = std::max(1, static_cast<int>(std::lround(o.lag / dt)));

  std::vector<char> moving(static_cast<std::size_t>(n), 0);
  std::vector<std::string> criteria;
  int joints = 0, gravity = 0, wrench = 0;
  for (int j = 0; j < s.q.cols(); ++j)
    joints += mark(s.q.col(j), k, tolerance(s.q.col(j), 1e-3), moving);
  if (!s.gravity_from_force && s.gravity.rows() == n) {
    // The gravity direction (a tilting platform): unit-vector components, rad.
    Eigen::MatrixXd dir = s.gravity;
    for (int i = 0; i < n; ++i)
      if (dir.row(i).norm() > 0) dir.row(i).normalize();
    for (int c = 0; c < 3; ++c) gravity += mark(dir.col(c), k, tolerance(dir.col(c), 1e-3), moving);
  }
  if (s.has_wrench()) {
    std::vector<double> magnitude(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) magnitude[i] = s.wrench.row(i).head<3>().norm();
    const double floor = 1e-3 * median(std::move(magnitude));
    for (int c = 0; c < 3; ++c)
      wrench += mark(s.wrench.col(c), k, tolerance(s.wrench.col(c), floor), moving);
  }
  // Continuous: the joints or the platform moved, or (gravity from the force)
  // the force turned. A wrench that jumps while nothing moves is a bump for
  // the outlier test, not a reason to cut the log.
  if (joints + gravity == 0 && !(s.gravity_from_force && wrench > 0)) return every_row(n);
  RestWindows out;
  out.rows = n;
  out.moving = joints + gravity + wrench;
  out.continuous = true;
  for (auto [count, name] : {std::pair{joints, "joints"}, {gravity, "gravity"}, {wrench, "wrench"}})
    if (count > 0) out.criterion += (out.criterion.empty() ? "" : ", ") + std::string(name);

  // Rest rows: not moving, not within `settle` after a motion nor `lag` before one.
  std::vector<char> rest(static_cast<std::size_t>(n), 1);
  const int settle = static_cast<int>(std::lround(o.settle / dt));
  for (int i = 0; i < n; ++i) {
    if (!moving[i]) continue;
    for (int r = std::max(0, i - k); r <= std::min(n - 1, i + settle); ++r) rest[r] = 0;
  }
  const int shortest = std::max(2, static_cast<int>(std::ceil(o.min_duration / dt)));
  for (int i = 0; i < n;) {
    if (!rest[i]) {
      ++i;
      continue;
    }
    int last = i;
    while (last + 1 < n && rest[last + 1]) ++last;
    if (last - i + 1 >= shortest) {
      out.windows.push_back({i, last});
      out.samples += last - i + 1;
    }
    i = last + 1;
  }
  // The settling the data show: blocks of 20 ms (at least 2 rows).
  if (o.trim && s.has_wrench())
    trim_settling(s.wrench, std::max(2, static_cast<int>(std::lround(0.02 / dt))), shortest, out,
                  dt);
  return out;
}

namespace {

// The noise of a wrench channel: 1.4826 median |x[i+1] - 2 x[i] + x[i-1]| / sqrt(6).
double second_difference_noise(const Eigen::Ref<const Eigen::VectorXd>& x) {
  std::vector<double> d;
  for (Eigen::Index i = 1; i + 1 < x.size(); ++i)
    d.push_back(std::abs(x[i + 1] - 2 * x[i] + x[i - 1]));
  return 1.4826 * median(std::move(d)) / std::sqrt(6.0);
}

// Central differences over k rows of the positions: velocity and acceleration at row i.
void differences(const Eigen::MatrixXd& q, const Eigen::VectorXd& t, int i, int k,
                 Eigen::VectorXd& qd, Eigen::VectorXd& qdd) {
  const double h1 = t[i] - t[i - k], h2 = t[i + k] - t[i];
  for (Eigen::Index j = 0; j < q.cols(); ++j) {
    const double d1 = (q(i, j) - q(i - k, j)) / h1, d2 = (q(i + k, j) - q(i, j)) / h2;
    qd[j] = 0.5 * (d1 + d2);
    qdd[j] = (d2 - d1) / (0.5 * (h1 + h2));
  }
}

// The quasi-static check of a continuous log (rest_windows.hpp).
void check_quasi_static(const Model& model, const Samples& s, const RestWindowOptions& o,
                        RestWindows& out) {
  const int n = s.size();
  const bool upstream = s.q_upstream.cols() == model.num_upstream_joints() &&
                        model.num_upstream_joints() > 0 && !s.has_sensor_motion();
  // Gravity that turns with nothing in the model to move it: a platform's motion, unknown.
  if (s.gravity_from_force || !s.has_wrench() || s.q.cols() != model.num_joints()) return;
  if (out.criterion.find("gravity") != std::string::npos && !upstream && !s.has_sensor_motion())
    return;
  const double dt = median_step(s.time);
  const int k = std::max(1, static_cast<int>(std::lround(o.lag / dt)));
  if (n < 2 * k + 3) return;
  double noise_f = std::numeric_limits<double>::infinity(), noise_m = noise_f;
  for (int c = 0; c < 3; ++c) {
    noise_f = std::min(noise_f, second_difference_noise(s.wrench.col(c)));
    noise_m = std::min(noise_m, second_difference_noise(s.wrench.col(3 + c)));
  }
  out.inertia_checked = true;
  out.noise_force = noise_f;
  out.noise_moment = noise_m;
  const Eigen::VectorXd pi = ParameterLayout::full().nominal(model);
  KinematicsData data(model);
  Eigen::MatrixXd Y(6, pi.size());
  const int nj = model.num_joints(), nu = model.num_upstream_joints();
  Eigen::VectorXd q(nj), qd(nj), qdd(nj), qu(nu), qdu(nu), qddu(nu);
  Eigen::Matrix<double, 9, 1> motion = Eigen::Matrix<double, 9, 1>::Zero();  // the sensor frame's
  bool slow = true;
  for (int i = k; i + k < n; ++i) {
    differences(s.q, s.time, i, k, qd, qdd);
    q = s.q.row(i).transpose();
    double speed = qd.size() ? qd.cwiseAbs().maxCoeff() : 0.0;
    if (upstream) {
      differences(s.q_upstream, s.time, i, k, qdu, qddu);
      qu = s.q_upstream.row(i).transpose();
      speed = std::max(speed, nu ? qdu.cwiseAbs().maxCoeff() : 0.0);
      upstream_sensor_frame(model, qu.data(), qdu.data(), qddu.data(), s.root_gravity, nullptr,
                            motion.data());
    } else if (s.has_sensor_motion()) {  // the sensor frame's motion as the log gives it
      motion = s.sensor_motion.row(i).transpose();
    }
    const FrameMotion sensor{motion.head<3>(), motion.segment<3>(3), motion.tail<3>()};
    forward_kinematics(model, data, q, qd, qdd, Eigen::Vector3d::Zero(), sensor);
    motion_regressor(model, data, Y);
    const Eigen::Matrix<double, 6, 1> w = Y * pi;
    out.max_speed = std::max(out.max_speed, speed);
    out.inertial_force = std::max(out.inertial_force, w.head<3>().norm());
    out.inertial_moment = std::max(out.inertial_moment, w.tail<3>().norm());
    if (out.inertial_force > o.quasi_static * noise_f ||
        out.inertial_moment > o.quasi_static * noise_m) {
      slow = false;
      break;  // a fast move: the windows stand (the numbers so far say why)
    }
  }
  if (!slow) return;
  // Every row a sample (as every_row), with the numbers that justify it.
  out.windowed_samples = out.samples;
  out.windows = every_row(n).windows;
  out.samples = n;
  out.continuous = false;
  out.trimmed = 0;
  out.longest_settling = 0.0;
  out.quasi_static = true;
}

}  // namespace

RestWindows find_rest_windows(const Model& model, const Samples& samples,
                              const RestWindowOptions& options) {
  RestWindows out = find_rest_windows(samples, options);
  if (out.continuous && options.quasi_static > 0) check_quasi_static(model, samples, options, out);
  return out;
}

Samples rest_samples(const Samples& s, const RestWindows& w) {
  if (!w.continuous) return s;
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(w.samples));
  for (const RestWindow& win : w.windows)
    for (int r = win.first; r <= win.last; ++r) rows.push_back(r);
  const auto pick = [&rows](auto& m) {
    if (m.rows() > 0) m = m(rows, Eigen::all).eval();
  };
  Samples out = s;
  for_each_joint_stream_array(out, pick);
  pick(out.wrench);
  pick(out.time);
  out.line.clear();
  out.block.clear();
  for (int r : rows) {
    if (!s.line.empty()) out.line.push_back(s.line[r]);
    if (!s.block.empty()) out.block.push_back(s.block[r]);
  }
  return out;
}

}  // namespace massid

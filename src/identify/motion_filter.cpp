// Zero-phase windowed-sinc filter with analytic derivative kernels (motion_filter.hpp).
#include "massid/identify/motion_filter.hpp"

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "identify/motion_pipeline.hpp"
#include "massid/core/errors.hpp"

namespace massid {

namespace {

constexpr double kPi = std::numbers::pi;

// sinc in y = π x: f(y) = sin(y)/y and its first two derivatives in y. Near 0
// the Taylor series f = Σ (-1)^n y^{2n}/(2n+1)! (12 terms: exact to rounding
// for |y| < 1); elsewhere the closed forms, whose cancellation is then mild.
void sinc_derivatives(double y, double* f, double* f1, double* f2) {
  if (std::abs(y) < 1.0) {
    const double y2 = y * y;
    double s0 = 0, s1 = 0, s2 = 0;
    // term_n = (-1)^n y^{2n} / (2n+1)!, from the highest order down (Horner-like sum).
    double coef[13];
    coef[0] = 1.0;
    for (int n = 1; n <= 12; ++n) coef[n] = -coef[n - 1] / ((2.0 * n) * (2.0 * n + 1.0));
    for (int n = 12; n >= 0; --n) {
      s0 = s0 * y2 + coef[n];
      if (n >= 1) {
        s1 = s1 * y2 + 2.0 * n * coef[n];                    // d/dy y^{2n} = 2n y^{2n-1}
        s2 = s2 * y2 + 2.0 * n * (2.0 * n - 1.0) * coef[n];  // 2n(2n-1) y^{2n-2}
      }
    }
    *f = s0;
    *f1 = s1 * y;  // Σ 2n c_n y^{2n-1}
    *f2 = s2;      // Σ 2n(2n-1) c_n y^{2n-2}
    return;
  }
  const double s = std::sin(y), c = std::cos(y);
  *f = s / y;
  *f1 = (y * c - s) / (y * y);
  *f2 = (2.0 * s - 2.0 * y * c - y * y * s) / (y * y * y);
}

// Blackman window on u in [-1, 1] and its derivatives in u.
void blackman(double u, double* w, double* w1, double* w2) {
  if (std::abs(u) >= 1.0) {
    *w = *w1 = *w2 = 0.0;
    return;
  }
  const double c1 = std::cos(kPi * u), s1 = std::sin(kPi * u);
  const double c2 = std::cos(2 * kPi * u), s2 = std::sin(2 * kPi * u);
  *w = 0.42 + 0.5 * c1 + 0.08 * c2;
  *w1 = -0.5 * kPi * s1 - 0.16 * kPi * s2;
  *w2 = -0.5 * kPi * kPi * c1 - 0.32 * kPi * kPi * c2;
}

// g_k <- g_k (alpha + beta tau_k^2) with alpha, beta solving
//   alpha P_a + beta P_{a+2} = ra,   alpha P_b + beta P_{b+2} = rb,
// where P_n = Σ g_k (sign tau_k)^n.
void taper(std::vector<double>& g, double dt, int H, double sign, int a, double ra, int b,
           double rb) {
  long double P[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (int k = -H; k <= H; ++k) {
    const long double tau = sign * k * dt;
    long double p = g[k + H];
    for (int n = 0; n < 8; ++n) {
      P[n] += p;
      p *= tau;
    }
  }
  const long double det = P[a] * P[b + 2] - P[a + 2] * P[b];
  const long double alpha = (ra * P[b + 2] - rb * P[a + 2]) / det;
  const long double beta = (rb * P[a] - ra * P[b]) / det;
  for (int k = -H; k <= H; ++k) {
    const long double tau = k * dt;
    g[k + H] = static_cast<double>(g[k + H] * (alpha + beta * tau * tau));
  }
}

}  // namespace

double default_cutoff(double rate) { return std::min(kMaxDefaultCutoff, rate / 20.0); }

int default_decimation(double rate, double cutoff) {
  // A rate read from rounded time stamps (999.9999999 Hz) still gives 50 at 10 Hz.
  const double d = std::floor(rate / (2.0 * cutoff) * (1.0 + 1e-9));
  if (!(d >= 1.0)) return 1;
  return d > 1e9 ? 1000000000 : static_cast<int>(d);
}

int kernel_samples(double dt, double cutoff) {
  return 2 * static_cast<int>(std::floor(kKernelSpan / (cutoff * dt) * (1.0 + 1e-9))) + 1;
}

int correlated_rows(const FilterKernels& k, int decimation) {
  return std::min((k.size() - 1) / std::max(decimation, 1), kMaxNoiseLags);
}

FilterPlan plan_filter(double dt, const MotionFilterOptions& options, const std::string& source,
                       int first_line, int last_line) {
  const double rate = 1.0 / dt;
  if (!(options.cutoff >= 0.0) || !std::isfinite(options.cutoff))
    throw InputError(fmt::format("{}: cutoff {} Hz is not positive", source, options.cutoff));
  const double cutoff = options.cutoff > 0.0 ? options.cutoff : default_cutoff(rate);
  if (cutoff >= 0.5 * rate)
    throw InputError(fmt::format(
        "{}:{}-{}: cutoff {:.6g} Hz is at or above the Nyquist limit {:.6g} Hz (half the sample "
        "rate {:.6g} Hz of t); choose a cutoff below {:.6g} Hz",
        source, first_line, last_line, cutoff, 0.5 * rate, rate, 0.5 * rate));
  if (options.decimation < 0)
    throw InputError(
        fmt::format("{}: decimation {} is negative (0: default)", source, options.decimation));
  FilterPlan plan;
  plan.decimation = options.decimation > 0 ? options.decimation : default_decimation(rate, cutoff);
  plan.kernels = make_kernels(dt, cutoff);
  return plan;
}

FilterKernels make_kernels(double dt, double cutoff) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError(fmt::format("filter: sample period {} s is not positive", dt));
  if (!(cutoff > 0.0) || !std::isfinite(cutoff))
    throw InputError(fmt::format("filter: cutoff {} Hz is not positive", cutoff));
  const double nyquist = 0.5 / dt;
  if (cutoff >= nyquist)
    throw InputError(
        fmt::format("filter: cutoff {:.6g} Hz is at or above the Nyquist limit {:.6g} Hz (half the "
                    "sample rate {:.6g} Hz)",
                    cutoff, nyquist, 1.0 / dt));
  const double T = kKernelSpan / cutoff;
  const double span = T / dt;
  if (span > 5e7)
    throw InputError(fmt::format(
        "filter: cutoff {} Hz at sample period {} s needs a kernel of {:.0f} samples (too long)",
        cutoff, dt, 2 * span + 1));
  FilterKernels K;
  K.dt = dt;
  K.cutoff = cutoff;
  const int H = static_cast<int>(std::floor(span * (1.0 + 1e-9)));
  K.half_width = H;
  K.smooth.assign(2 * H + 1, 0.0);
  K.first.assign(2 * H + 1, 0.0);
  K.second.assign(2 * H + 1, 0.0);
  const double A = 2.0 * cutoff;        // h = A f(a tau) w(b tau)
  const double a = 2.0 * kPi * cutoff;  // dy/dtau, y = pi (2 fc tau)
  const double b = 1.0 / T;             // du/dtau
  // Raw kernel and its analytic derivatives at k >= 0 (mirrored below).
  std::vector<double> h0(H + 1), h1(H + 1), h2(H + 1);
  for (int k = 0; k <= H; ++k) {
    const double tau = k * dt;
    double f, f1, f2, w, w1, w2;
    sinc_derivatives(a * tau, &f, &f1, &f2);
    blackman(b * tau, &w, &w1, &w2);
    h0[k] = A * f * w;
    h1[k] = A * (a * f1 * w + b * f * w1);
    h2[k] = A * (a * a * f2 * w + 2.0 * a * b * f1 * w1 + b * b * f * w2);
  }
  // Smoothing kernel s = h (alpha + beta tau^2), alpha and beta from the discrete moments
  // (Σ s_k = 1, Σ s_k tau_k^2 = 0); its analytic derivatives
  //   s' = h' p + h p',  s'' = h'' p + 2 h' p' + h p''  (p = alpha + beta tau^2)
  // are the velocity and acceleration kernels, so that they are the derivatives of the smoothed
  // position (responses i w S(f) and -w^2 S(f)) and share its flat passband.
  long double m0 = 0, m2 = 0, m4 = 0;  // Σ h_k u_k^n, u = tau/T
  for (int k = -H; k <= H; ++k) {
    const long double u2 = static_cast<long double>(k * dt / T) * (k * dt / T);
    const long double v = h0[std::abs(k)] * dt;
    m0 += v;
    m2 += v * u2;
    m4 += v * u2 * u2;
  }
  const long double det = m0 * m4 - m2 * m2;
  const double alpha = static_cast<double>(m4 / det);  // in u: p(u) = alpha + beta u^2
  const double beta = static_cast<double>(-m2 / det);
  for (int k = 0; k <= H; ++k) {
    const double u = k * dt / T;
    const double p = alpha + beta * u * u, p1 = 2.0 * beta * u * b, p2 = 2.0 * beta * b * b;
    const double s0 = h0[k] * p, s1 = h1[k] * p + h0[k] * p1,
                 s2 = h2[k] * p + 2.0 * h1[k] * p1 + h0[k] * p2;
    K.smooth[H + k] = K.smooth[H - k] = s0 * dt;
    K.first[H + k] = s1 * dt;
    K.first[H - k] = -s1 * dt;
    K.second[H + k] = K.second[H - k] = s2 * dt;
  }
  K.first[H] = 0.0;
  // Exact on cubics (header): moments of tau for even kernels, of -tau for the odd one.
  taper(K.smooth, dt, H, 1.0, 0, 1.0, 2, 0.0);  // Σ s = 1, Σ s tau^2 = 0
  taper(K.first, dt, H, -1.0, 1, 1.0, 3, 0.0);  // Σ f (-tau) = 1, Σ f (-tau)^3 = 0
  taper(K.second, dt, H, 1.0, 2, 2.0, 0, 0.0);  // Σ d tau^2 = 2, Σ d = 0
  return K;
}

MotionFilter::MotionFilter(const FilterKernels& k, int width, int num_derived, int decimation)
    : k_(k), width_(width), nd_(num_derived), decimation_(decimation), len_(k.size()) {
  if (width < 0 || num_derived < 0 || num_derived > width)
    throw std::invalid_argument("MotionFilter: need 0 <= num_derived <= width");
  if (decimation < 1) throw std::invalid_argument("MotionFilter: decimation must be >= 1");
  if (k.half_width < 1 || static_cast<int>(k.smooth.size()) != len_ ||
      static_cast<int>(k.first.size()) != len_ || static_cast<int>(k.second.size()) != len_)
    throw std::invalid_argument("MotionFilter: kernels of inconsistent length");
  // Window slot j holds x_{i-H+j}, which pairs with weight index k = H - j, i.e. k + H = 2H - j.
  rev_smooth_.assign(k.smooth.rbegin(), k.smooth.rend());
  rev_first_.assign(k.first.rbegin(), k.first.rend());
  rev_second_.assign(k.second.rbegin(), k.second.rend());
  buffer_.assign(static_cast<std::size_t>(2 * len_) * std::max(width_, 1), 0.0);
  times_.assign(len_, 0.0);
  lines_.assign(len_, 0);
  out_.assign(width_ + 2 * nd_, 0.0);
}

void MotionFilter::reset() {
  count_ = 0;
  ready_ = false;
}

void MotionFilter::push(const double* row, double t, int line) {
  if (ready_) throw std::logic_error("MotionFilter::push: pop() the ready row first");
  if (!std::isfinite(t))
    throw InputError(
        fmt::format("{}: t = {} is not a finite time", detail::where(source_, line), t));
  if (count_ > 0) {
    const double step = t - last_t_;
    if (step <= 0.0) detail::OrderError{line, last_line_, t, last_t_}.raise(source_);
    const double dev = std::abs(step - k_.dt) / k_.dt;
    if (dev > kUniformTolerance) {
      if (step > 1.5 * k_.dt)
        throw InputError(fmt::format(
            "{}: gap in t: step {:.6g} s from line {} where the sample period is {:.6g} s "
            "(about {:.0f} samples missing); the filter needs uniformly sampled t",
            detail::where(source_, line), step, last_line_, k_.dt, std::round(step / k_.dt) - 1));
      throw InputError(fmt::format(
          "{}: non-uniform t: step {:.6g} s from line {} differs from the sample period "
          "{:.6g} s by {:.3g}% (more than {}%); the filter needs uniformly sampled t",
          detail::where(source_, line), step, last_line_, k_.dt, 100 * dev,
          100 * kUniformTolerance));
    }
  }
  last_t_ = t;
  last_line_ = line;
  const int slot = static_cast<int>(count_ % len_);
  double* a = buffer_.data() + static_cast<std::size_t>(slot) * width_;
  double* b = buffer_.data() + static_cast<std::size_t>(slot + len_) * width_;
  for (int c = 0; c < width_; ++c) a[c] = b[c] = row[c];
  times_[slot] = t;
  lines_[slot] = line;
  ++count_;
  if (count_ >= len_ && (count_ - len_) % decimation_ == 0) {
    compute();
    ready_ = true;
  }
}

void MotionFilter::compute() {
  // The last len_ rows are contiguous at slots s+1 .. s+len_ (s: slot of the newest row).
  const int s = static_cast<int>((count_ - 1) % len_);
  const double* w = buffer_.data() + static_cast<std::size_t>(s + 1) * width_;
  using Map = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
  using Vec = Eigen::Map<const Eigen::VectorXd>;
  using Out = Eigen::Map<Eigen::VectorXd>;
  const Map all(w, width_, len_, Eigen::OuterStride<>(width_));
  Out(out_.data(), width_).noalias() = all * Vec(rev_smooth_.data(), len_);
  if (nd_ > 0) {
    const Map derived(w, nd_, len_, Eigen::OuterStride<>(width_));
    Out(out_.data() + width_, nd_).noalias() = derived * Vec(rev_first_.data(), len_);
    Out(out_.data() + width_ + nd_, nd_).noalias() = derived * Vec(rev_second_.data(), len_);
  }
  const int centre = static_cast<int>((count_ - 1 - k_.half_width) % len_);
  out_t_ = times_[centre];
  out_line_ = lines_[centre];
}

bool MotionFilter::pop(double* value, double* first, double* second, double* t, int* line) {
  if (!ready_) return false;
  ready_ = false;
  if (value) std::copy_n(out_.data(), width_, value);
  if (first) std::copy_n(out_.data() + width_, nd_, first);
  if (second) std::copy_n(out_.data() + width_ + nd_, nd_, second);
  if (t) *t = out_t_;
  if (line) *line = out_line_;
  return true;
}

}  // namespace massid

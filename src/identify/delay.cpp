#include "massid/identify/delay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/median.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"

namespace massid {

namespace {

void require_time(const Samples& raw) {
  if (raw.time.size() != raw.size() || raw.size() < 3)
    throw InputError(fmt::format("{}: the wrench's delay needs the time column t", raw.source),
                     {{Hint::Setting::Delay, ""}});
}

// The sample period of a log with t: its median step.
double sample_period(const Samples& raw) {
  require_time(raw);
  const Eigen::VectorXd steps = raw.time.tail(raw.size() - 1) - raw.time.head(raw.size() - 1);
  return detail::median(std::vector<double>(steps.begin(), steps.end()));
}

// chi^2 of the fit at `delay` with the noise `sigma` (per axis).
double chi2_at(const Model& model, const BaseParameters& base, const Samples& raw, double delay,
               int margin, const IdentifyOptions& options, const MotionDataOptions& data,
               const Eigen::Matrix<double, 6, 1>& sigma) {
  const Samples s = prepare_motion_samples(model, delay_wrench(raw, delay, margin), data);
  const IdentifySummary f = identify(model, base, s, options);
  double chi2 = 0.0;
  for (int k = 0; k < 6; ++k) chi2 += f.samples * std::pow(f.residual_rms[k] / sigma[k], 2);
  return chi2;
}

}  // namespace

Samples delay_wrench(const Samples& raw, double delay, int margin) {
  require_time(raw);
  const int n = raw.size();
  const int rows = n - 2 * margin;
  if (margin < 0 || rows < 2)
    throw InputError(
        fmt::format("{}: the log is too short for a delay of {:.3g} s", raw.source, delay));
  // Row i keeps its wrench (its noise untouched) and takes the joint stream
  // at t_i - delay: linear interpolation of the smooth signals between the
  // rows around it.
  std::vector<int> at(static_cast<std::size_t>(rows));
  std::vector<double> frac(static_cast<std::size_t>(rows));
  int j = 0;
  for (int i = 0; i < rows; ++i) {
    const double t = raw.time[margin + i] - delay;
    while (j + 2 < n && raw.time[j + 1] <= t) ++j;
    while (j > 0 && raw.time[j] > t) --j;
    const double span = raw.time[j + 1] - raw.time[j];
    at[i] = j;
    frac[i] = span > 0 ? std::clamp((t - raw.time[j]) / span, 0.0, 1.0) : 0.0;
  }
  const auto moved = [&](Eigen::MatrixXd& m) {
    if (m.rows() == 0) return;
    Eigen::MatrixXd out(rows, m.cols());
    for (int i = 0; i < rows; ++i)
      out.row(i) = (1 - frac[i]) * m.row(at[i]) + frac[i] * m.row(at[i] + 1);
    m = std::move(out);
  };
  Samples out = raw;
  for_each_joint_stream_array(out, moved);
  if (raw.wrench.rows() > 0) out.wrench = raw.wrench.middleRows(margin, rows);
  out.time = raw.time.segment(margin, rows);
  if (!raw.line.empty())
    out.line.assign(raw.line.begin() + margin, raw.line.begin() + margin + rows);
  if (!raw.block.empty())
    out.block.assign(raw.block.begin() + margin, raw.block.begin() + margin + rows);
  return out;
}

Samples delay_joint_stream(Samples samples, double delay, const std::string& model_source,
                           std::string* note) {
  if (note) note->clear();
  if (delay == 0.0) return samples;
  if (samples.time.size() != samples.size() || samples.size() < 3)
    throw InputError(fmt::format(
        "{}: {} has the wrench's clock delay ({:.4g} ms, identify --delay): the prediction "
        "applies it from the time column t, which this log lacks; add t",
        samples.source, model_source, 1e3 * delay));
  const double first = samples.time[0], last = samples.time[samples.size() - 1];
  int held = 0;
  for (int i = 0; i < samples.size(); ++i)
    held += samples.time[i] - delay < first || samples.time[i] - delay > last;
  if (note)
    *note = fmt::format(
        "{}: the wrench's clock delay of {:.4g} ms ({}) applied: each row predicted for the "
        "joint state {:.4g} ms {}{}",
        samples.source, 1e3 * delay, model_source, 1e3 * std::abs(delay),
        delay > 0 ? "earlier" : "later",
        held > 0 ? fmt::format("; {} row(s) at the log's {} take its {} row's", held,
                               delay > 0 ? "start" : "end", delay > 0 ? "first" : "last")
                 : "");
  return delay_wrench(samples, delay, 0);
}

DelayEstimate estimate_delay(const Model& model, const Samples& raw, bool offset,
                             const IdentifyOptions& options, const MotionDataOptions& data,
                             double max_delay) {
  const double dt = sample_period(raw);
  if (!(dt > 0) || !(max_delay > 0))
    throw InputError(
        fmt::format("{}: estimating the wrench's delay needs increasing times t", raw.source),
        {{Hint::Setting::Delay, "auto"}});
  const int margin = static_cast<int>(std::ceil(max_delay / dt)) + 1;
  IdentifyOptions o = options;
  o.robust = false;         // the scan compares plain fits,
  o.weight_iterations = 1;  // weighted once: chi^2 uses the noise of the fit at delay 0
  const Samples s0 = prepare_motion_samples(model, delay_wrench(raw, 0.0, margin), data);
  const BaseParameters base = find_base_parameters(model, motion_base_options(s0, offset));
  const Eigen::Matrix<double, 6, 1> sigma = identify(model, base, s0, o).sigma;

  DelayEstimate d;
  d.applied = d.estimated = true;
  const auto chi2 = [&](double delay) {
    for (const auto& [at, value] : d.scan)
      if (std::abs(at - delay) < 1e-12) return value;
    const double c = chi2_at(model, base, raw, delay, margin, o, data, sigma);
    d.scan.push_back({delay, c});
    return c;
  };
  // Coarse, then fine around the best, then the parabola through the best three.
  const double coarse = max_delay / 8;
  double best = 0.0;
  for (int k = -8; k <= 8; ++k)
    if (chi2(k * coarse) < chi2(best)) best = k * coarse;
  if (std::abs(best) > max_delay - 0.5 * coarse)
    throw InputError(fmt::format("{}: the wrench's delay is beyond the +-{:.3g} ms scanned (the "
                                 "best fit is at {:.3g} ms): "
                                 "check the clocks, or give the delay",
                                 raw.source, 1e3 * max_delay, 1e3 * best),
                     {{Hint::Setting::Delay, ""}});
  const double h = coarse / 4;
  double fine = best;
  for (int k = -4; k <= 4; ++k)
    if (chi2(best + k * h) < chi2(fine)) fine = best + k * h;
  const double lo = chi2(fine - h), mid = chi2(fine), hi = chi2(fine + h);
  const double curvature = (lo - 2 * mid + hi) / (h * h);
  if (curvature > 0) {
    d.value = fine + 0.5 * h * (lo - hi) / (lo - 2 * mid + hi);
    d.std = std::sqrt(2.0 / curvature);
  } else {
    d.value = fine;
    d.std = h;
  }
  std::sort(d.scan.begin(), d.scan.end());
  return d;
}

Samples aligned_motion_samples(const Model& model, Samples raw, bool offset,
                               const IdentifyOptions& options, const MotionDataOptions& data,
                               DelayEstimate* delay, MotionDataReport* report) {
  DelayEstimate d;
  if (options.delay_auto) {
    d = estimate_delay(model, raw, offset, options, data, options.max_delay);
  } else if (options.delay) {
    d.applied = true;
    d.value = *options.delay;
  }
  if (d.applied) {
    const double dt = sample_period(raw);
    const double reach = std::max(std::abs(d.value), options.delay_auto ? options.max_delay : 0.0);
    raw = delay_wrench(raw, d.value, static_cast<int>(std::ceil(reach / dt)) + 1);
  }
  if (delay) *delay = d;
  return prepare_motion_samples(model, std::move(raw), data, report);
}

}  // namespace massid

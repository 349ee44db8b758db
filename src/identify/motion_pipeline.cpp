// The motion row pipeline's pieces that are not templates (motion_pipeline.hpp),
// and filter_motion: the pipeline over samples in memory.
#include "identify/motion_pipeline.hpp"

#include <cmath>

#include "core/median.hpp"

namespace massid {

namespace detail {

SampleCollector::SampleCollector(const MotionPlan& p) : plan_(p) {
  const int nqd = p.final_qd ? p.nj : 0, nu = p.up ? p.nu : 0, nqdu = p.final_qdu ? p.nu : 0;
  groups_ = {{&FinalRow::q, &Samples::q, p.nj, {}},
             {&FinalRow::qd, &Samples::qd, nqd, {}},
             {&FinalRow::qdd, &Samples::qdd, nqd, {}},
             {&FinalRow::qu, &Samples::q_upstream, nu, {}},
             {&FinalRow::qdu, &Samples::qd_upstream, nqdu, {}},
             {&FinalRow::qddu, &Samples::qdd_upstream, nqdu, {}},
             {&FinalRow::g, &Samples::gravity, 3, {}},
             {&FinalRow::sm, &Samples::sensor_motion, p.final_sensor ? 9 : 0, {}},
             {&FinalRow::w, &Samples::wrench, 6, {}}};
}

void SampleCollector::add(const FinalRow& r) {
  ++n_;
  for (Group& g : groups_)
    if (g.n > 0) g.values.insert(g.values.end(), r.*g.from, r.*g.from + g.n);
  t_.push_back(r.t);
  line_.push_back(r.line);
  block_.push_back(static_cast<int>(r.block));
}

Samples SampleCollector::take(const std::string& source) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const MotionPlan& p = plan_;
  Samples s;
  s.source = source;
  for (const Group& g : groups_) s.*g.to = Eigen::Map<const RowMajor>(g.values.data(), n_, g.n);
  if (p.cols.time >= 0) s.time = Eigen::Map<const Eigen::VectorXd>(t_.data(), n_);
  s.line = std::move(line_);
  if (p.cols.block >= 0) s.block = std::move(block_);
  s.gravity_from_force = p.cols.gravity_from_force;
  s.gravity_from_upstream = p.cols.gravity_from_upstream;
  s.root_gravity = p.cols.root_gravity;
  s.derivatives_filtered = p.derived;
  return s;
}

SampleColumns columns_of(const Samples& s) {
  SampleColumns c;
  c.source = s.source;
  c.num_joints = static_cast<int>(s.q.cols());
  c.num_upstream = static_cast<int>(s.q_upstream.cols());
  const int nj = c.num_joints, nu = c.num_upstream;
  int at = 0;
  const auto take = [&](bool present, int n) {
    if (!present) return -1;
    const int o = at;
    at += n;
    return o;
  };
  take(true, nj);  // q: first, as read_row takes it
  c.qd = take(s.qd.cols() > 0, nj);
  c.qdd = take(s.qdd.cols() > 0, nj);
  c.q_up = take(nu > 0, nu);
  c.qd_up = take(nu > 0 && s.qd_upstream.cols() > 0, nu);
  c.qdd_up = take(nu > 0 && s.qdd_upstream.cols() > 0, nu);
  c.gravity = take(true, 3);
  c.sensor = take(s.has_sensor_motion(), 9);
  c.wrench = take(true, 6);
  c.time = take(s.time.size() == s.size(), 1);
  c.block = take(s.block.size() == static_cast<std::size_t>(s.size()), 1);
  c.num_values = at;
  c.motion = true;
  c.gravity_from_force = s.gravity_from_force;
  c.gravity_from_upstream = s.gravity_from_upstream;
  c.root_gravity = s.root_gravity;
  return c;
}

void samples_row(const Samples& s, const SampleColumns& c, int i, double* v) {
  const auto put = [&](int at, const Eigen::MatrixXd& m) {
    if (at < 0) return;
    for (Eigen::Index j = 0; j < m.cols(); ++j) v[at + j] = m(i, j);
  };
  put(0, s.q);
  put(c.qd, s.qd);
  put(c.qdd, s.qdd);
  put(c.q_up, s.q_upstream);
  put(c.qd_up, s.qd_upstream);
  put(c.qdd_up, s.qdd_upstream);
  if (s.gravity.cols() == 3)
    put(c.gravity, s.gravity);
  else
    std::fill_n(v + c.gravity, 3, 0.0);
  put(c.sensor, s.sensor_motion);
  if (s.has_wrench())
    put(c.wrench, s.wrench);
  else
    std::fill_n(v + c.wrench, 6, 0.0);
  if (c.time >= 0) v[c.time] = s.time[i];
  if (c.block >= 0) v[c.block] = s.block[i];
}

}  // namespace detail

Samples filter_motion(const Samples& samples, const MotionFilterOptions& options,
                      FilterKernels* used) {
  const std::string source = samples.source.empty() ? "data" : samples.source;
  const int n = samples.size();
  const auto line_of = [&](int i) {
    return i < static_cast<int>(samples.line.size()) ? samples.line[i] : i + 1;
  };
  if (samples.time.size() != n)
    throw InputError(
        fmt::format("{}: filtering the motion needs the time column t (to derive velocities and "
                    "accelerations from the positions)",
                    source));
  const bool blocks = samples.block.size() == static_cast<std::size_t>(n);
  for (const Eigen::MatrixXd* m :
       {&samples.qd, &samples.qdd, &samples.q_upstream, &samples.qd_upstream, &samples.qdd_upstream,
        &samples.gravity, &samples.sensor_motion, &samples.wrench})
    if (m->cols() > 0 && m->rows() != n)
      throw std::invalid_argument("filter_motion: a Samples matrix has the wrong number of rows");

  // Order, then the sample period: the median step within blocks (what the
  // file's scan of t finds, scan_log_times).
  std::vector<double> steps;
  steps.reserve(static_cast<std::size_t>(std::max(n - 1, 0)));
  for (int i = 1; i < n; ++i) {
    if (blocks && samples.block[i] != samples.block[i - 1]) continue;
    const double t0 = samples.time[i - 1], t1 = samples.time[i];
    if (!std::isfinite(t1) || !std::isfinite(t0))
      throw InputError(fmt::format("{}: t = {} is not a finite time",
                                   detail::where(source, line_of(std::isfinite(t0) ? i : i - 1)),
                                   std::isfinite(t0) ? t1 : t0));
    if (t1 <= t0) detail::OrderError{line_of(i), line_of(i - 1), t1, t0}.raise(source);
    steps.push_back(t1 - t0);
  }
  detail::check_time_series(source, n, static_cast<long long>(steps.size()), line_of(0));
  const double dt = detail::median(std::move(steps));

  // The pipeline over one block that holds every sample, without resolving
  // the upstream joints (prepare_motion_samples does, after the filter).
  detail::SampleColumns cols = detail::columns_of(samples);
  cols.source = source;
  const detail::MotionPlan plan(nullptr, cols, false);
  const FilterPlan f = plan_filter(dt, options, source, line_of(0), line_of(n - 1));
  detail::ParsedBlock b;
  b.stride = plan.stride;
  b.rows.resize(static_cast<std::size_t>(n) * plan.stride);
  std::vector<double> v(cols.num_values);
  for (int i = 0; i < n; ++i) {
    detail::samples_row(samples, cols, i, v.data());
    plan.read_row(v.data(), b.rows.data() + static_cast<std::size_t>(i) * plan.stride);
    b.line.push_back(line_of(i));
  }
  b.n = n;
  detail::Carry carry;
  detail::sequence_rows(plan, &f, carry, b);
  detail::check_run(plan, f, carry);
  detail::SampleCollector out(plan);
  detail::prepared_rows(plan, &f, b, [&](const detail::FinalRow& r) { out.add(r); });
  Samples s = out.take(samples.source);
  if (!samples.has_wrench()) s.wrench.resize(s.size(), 0);
  if (samples.gravity.cols() != 3) s.gravity.resize(s.size(), 0);
  s.gravity_from_force = samples.gravity_from_force;
  s.gravity_from_upstream = samples.gravity_from_upstream;
  s.derivatives_filtered = true;
  s.noise_lags = correlated_rows(f.kernels, f.decimation);
  if (used) *used = f.kernels;
  return s;
}

}  // namespace massid

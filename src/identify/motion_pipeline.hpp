// The motion row pipeline, the one code of every motion log: the rows of a
// source (a parsed block of a CSV file, or Samples in memory) laid out by a
// MotionPlan, sequenced into runs (a block column restarts the filter; a run
// shorter than the filter is an error), filtered by the zero-phase filter of
// motion_filter.hpp with the rows before a block as its margin, and
// resolved (gravity and sensor motion from the filtered upstream joints).
// filter_motion (in memory) runs it over one block holding every row;
// identify_motion_csv (motion_csv_identify.cpp) over the file's blocks on
// threads. So the two cannot diverge.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "io/csv_stream.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/motion_filter.hpp"
#include "massid/identify/streaming.hpp"

namespace massid::detail {

// How the rows of a motion log become samples, as read_samples and
// prepare_motion_samples make them: the values of a parsed line, gravity from
// the force or from the upstream joints, their sensor motion (read_samples);
// filter_motion's layout of a row when velocities are derived (derived groups
// first, then every smoothed column) and resolve_upstream after the filter.
struct MotionPlan {
  const Model* model = nullptr;
  SampleColumns cols;
  int nj = 0, nu = 0;
  bool has_qd = false, has_qdu = false, has_sm_columns = false, up = false;
  // read_samples
  bool read_sensor = false;  // sensor motion from the upstream joints' velocities
  bool read_resolve = false;
  bool has_sensor = false;  // the read samples have sensor motion
  // prepare_motion_samples
  bool derived = false;
  bool derive_q = false, derive_up = false;  // the filter derives these groups
  int width = 0, nd = 0;                     // the row (filter) layout
  int o_q = -1, o_qd = -1, o_qdd = -1, o_qu = -1, o_qdu = -1, o_qddu = -1, o_g = -1, o_sm = -1,
      o_w = -1;
  int d_q = -1, d_qu = -1;  // derived groups: offsets in the filter's first and second
  int stride = 0;           // a stored row: width values, t, block
  bool post_moving = false, post_resolve = false;  // after the filter
  bool final_sensor = false;                       // the prepared samples have sensor motion
  bool final_qd = false, final_qdu = false;        // they have qd, qdd (qd_up, qdd_up)

  // `resolve`: gravity and sensor motion from the upstream joints (a model
  // is needed); without, the columns are taken as they are (filter_motion).
  MotionPlan(const Model* m, SampleColumns bound, bool resolve = true)
      : model(m), cols(std::move(bound)) {
    nj = cols.num_joints;
    nu = cols.num_upstream;
    has_qd = cols.qd >= 0;
    up = cols.q_up >= 0 && nu > 0;
    has_qdu = up && cols.qd_up >= 0;
    has_sm_columns = cols.sensor >= 0;
    read_sensor = has_qdu && !has_sm_columns;
    if (!resolve) read_sensor = false;
    read_resolve = resolve && up && (cols.gravity_from_upstream || read_sensor);
    has_sensor = has_sm_columns || read_sensor;
    const bool joints_missing = nj > 0 && !has_qd;
    const bool upstream_missing = up && !has_qdu && !has_sensor;
    derived = joints_missing || upstream_missing;
    derive_q = derived && !has_qd && nj > 0;
    derive_up = derived && !has_qdu && up;
    int c = 0, d = 0;
    const auto take = [&](int n) {
      const int at = c;
      c += n;
      return at;
    };
    if (derive_q) {
      o_q = take(nj);
      d_q = d;
      d += nj;
    }
    if (derive_up) {
      o_qu = take(nu);
      d_qu = d;
      d += nu;
    }
    nd = d;
    if (!derive_q) {
      o_q = take(nj);
      if (has_qd) {
        o_qd = take(nj);
        o_qdd = take(nj);
      }
    }
    if (!derive_up && up) {
      o_qu = take(nu);
      if (has_qdu) {
        o_qdu = take(nu);
        o_qddu = take(nu);
      }
    }
    o_g = take(3);
    if (has_sensor) o_sm = take(9);
    o_w = take(6);
    width = c;
    stride = width + 2;
    if (derived && resolve) {
      post_moving = up && (has_qdu || derive_up) && !has_sensor;
      post_resolve = up && (cols.gravity_from_upstream || post_moving);
    }
    final_sensor = has_sensor || post_moving;
    final_qd = has_qd || derive_q;
    final_qdu = has_qdu || derive_up;
  }

  // A parsed line's values (SampleColumns layout) as a stored row.
  void read_row(const double* v, double* row) const {
    std::copy_n(v, nj, row + o_q);  // joints come first in the values
    if (has_qd) {
      std::copy_n(v + cols.qd, nj, row + o_qd);
      std::copy_n(v + cols.qdd, nj, row + o_qdd);
    }
    if (up) {
      std::copy_n(v + cols.q_up, nu, row + o_qu);
      if (has_qdu) {
        std::copy_n(v + cols.qd_up, nu, row + o_qdu);
        std::copy_n(v + cols.qdd_up, nu, row + o_qddu);
      }
    }
    std::copy_n(v + cols.gravity, 3, row + o_g);  // read, or from the force
    if (has_sm_columns) std::copy_n(v + cols.sensor, 9, row + o_sm);
    std::copy_n(v + cols.wrench, 6, row + o_w);
    if (read_resolve)
      upstream_sensor_frame(*model, v + cols.q_up, has_qdu ? v + cols.qd_up : nullptr,
                            has_qdu ? v + cols.qdd_up : nullptr, cols.root_gravity,
                            cols.gravity_from_upstream ? row + o_g : nullptr,
                            read_sensor ? row + o_sm : nullptr);
    row[width] = cols.time >= 0 ? v[cols.time] : 0.0;
    row[width + 1] = cols.block >= 0 ? v[cols.block] : 0.0;
  }
};

// motion_base_options' fixed gravity: every sample's within this of the first's, g0.
inline double fixed_gravity_tolerance(const Eigen::Vector3d& g0) {
  return 1e-6 * std::max(g0.norm(), 1e-300);
}

// One prepared sample (what prepare_motion_samples' Samples holds in a row).
struct FinalRow {
  const double *q, *qd, *qdd, *qu, *qdu, *qddu, *g, *sm, *w;
  double t;
  double block;
  int line;
  MotionRow motion() const { return MotionRow{q, qd, qdd, g, sm, w, block}; }
};

// A block of the file parsed into rows (stride values each).
struct ParsedBlock {
  std::vector<double> rows;
  std::vector<int> line;  // relative to the block's first line, then absolute
  std::size_t lines = 0;  // lines starting in the block
  int n = 0;
  // From the sequential stage: the rows before the block that the filter
  // needs (same run), and whether the block's first row continues that run.
  std::vector<double> margin;
  std::vector<int> margin_line;
  int margin_rows = 0;
  bool continues = false;
  int stride = 0;
  const double* row(int i) const { return rows.data() + static_cast<size_t>(i) * stride; }
};

// (`storage`: a buffer to reuse for the rows, so that blocks do not fault in
// fresh pages.)
inline ParsedBlock parse_rows(std::string_view text, const MotionPlan& plan, size_t begin,
                              size_t end, std::vector<double> storage = {}) {
  ParsedBlock b;
  b.stride = plan.stride;
  b.rows = std::move(storage);
  b.rows.clear();
  const SampleColumns& c = plan.cols;
  const size_t stride = static_cast<size_t>(plan.stride);
  b.lines = parse_block(text, c, begin, end, [&](const double* v, size_t pos, int line) {
    if (c.block >= 0 && !is_block_number(v[c.block])) throw_not_integer(text, pos, c, v[c.block]);
    const size_t at = b.rows.size();
    b.rows.resize(at + stride);
    plan.read_row(v, b.rows.data() + at);
    b.line.push_back(line);
    ++b.n;
  });
  return b;
}

// A stored row as a prepared sample (no filter).
inline FinalRow unfiltered(const MotionPlan& p, const double* r, int line) {
  const auto at = [r](int offset) { return offset >= 0 ? r + offset : nullptr; };  // -1: none
  return FinalRow{at(p.o_q), at(p.o_qd), at(p.o_qdd), at(p.o_qu), at(p.o_qdu),    at(p.o_qddu),
                  at(p.o_g), at(p.o_sm), at(p.o_w),   r[p.width], r[p.width + 1], line};
}

// What the sequential stage carries from block to block.
struct Carry {
  int line_base = 0;  // file line of the next block's first line
  long long rows = 0;
  bool any = false;
  int last_line = 0;
  long long run_length = 0;  // rows of the current run so far
  int run_first_line = 0;
  double run_block = 0.0;
  std::vector<double> tail;  // the current run's last rows (at most `keep`), stride each
  std::vector<int> tail_line;
};

inline std::string where(const std::string& source, int line) {
  return fmt::format("{}:{}", source, line);
}

// A motion log whose velocities and accelerations are to be derived needs t.
inline void require_time_column(const std::string& source, bool has_time) {
  if (!has_time)
    throw InputError(fmt::format(
        "{}: a motion log needs joint velocities and accelerations: columns JOINT_vel and "
        "JOINT_acc for every joint, or a time column t to derive them from the positions",
        source));
}

// filter_motion's errors for a log that is no time series: fewer than two
// samples (`rows`), or no two in one block (no `steps` within blocks).
inline void check_time_series(const std::string& source, long long rows, long long steps,
                              int first_line) {
  if (rows < 2)
    throw InputError(fmt::format("{}: only {} sample(s): filtering the motion needs a time series",
                                 rows > 0 ? where(source, first_line) : source, rows));
  if (steps == 0)
    throw InputError(
        fmt::format("{}: every block has a single sample: filtering the motion needs a time series",
                    where(source, first_line)));
}

// filter_motion's message for a run (block) shorter than the filter.
[[noreturn]] inline void throw_short_run(const MotionPlan& plan, const FilterPlan& f, long long m,
                                         int first_line, int last_line, double block) {
  const double dt = f.kernels.dt, rate = 1.0 / dt;
  const int L = f.kernels.size(), H = f.kernels.half_width;
  throw InputError(
      fmt::format(
          "{}: only {} samples (lines {}-{}{}, {:.4g} s at {:.6g} Hz) but the filter at cutoff "
          "{:.6g} Hz needs at least {} ({} on each side of a filtered sample, {:.4g} s); "
          "use a higher cutoff or a longer log",
          where(plan.cols.source, first_line), m, first_line, last_line,
          plan.cols.block >= 0 ? fmt::format(", block {}", static_cast<int>(block)) : std::string(),
          static_cast<double>(m - 1) * dt, rate, f.kernels.cutoff, L, H, (L - 1) * dt),
      {{Hint::Setting::Cutoff, "higher"}});
}

// throw_short_run for the current run when it is shorter than the filter.
inline void check_run(const MotionPlan& plan, const FilterPlan& f, const Carry& c) {
  if (c.any && c.run_length < f.kernels.size())
    throw_short_run(plan, f, c.run_length, c.run_first_line, c.last_line, c.run_block);
}

// The sequential stage of block b: absolute lines; with the filter, the runs
// (a short one is filter_motion's error) and the margin of rows before the
// block that its filter needs.
inline void sequence_rows(const MotionPlan& plan, const FilterPlan* f, Carry& c, ParsedBlock& b) {
  for (int& l : b.line) l += c.line_base;
  c.line_base += static_cast<int>(b.lines);
  c.rows += b.n;
  if (!f) return;
  const int stride = plan.stride, L = f->kernels.size(), D = f->decimation;
  const size_t keep = static_cast<size_t>(L) + D - 2;  // rows a margin can need
  const bool blocks = plan.cols.block >= 0;
  // The margin: rows [s, run_length) of the current run, s a multiple of D
  // at most run_length - L + 1, so that a filter restarted at row s emits
  // filter_motion's rows (its decimation phase counts from the run's start).
  b.continues = c.any && b.n > 0 && (!blocks || b.row(0)[plan.width + 1] == c.run_block);
  if (b.continues) {
    const long long f0 = c.run_length;
    const long long s = std::max<long long>(0, f0 - L + 1) / D * D;
    const int m = static_cast<int>(f0 - s);
    const int held = static_cast<int>(c.tail_line.size());
    b.margin_rows = m;
    b.margin.assign(c.tail.end() - static_cast<std::ptrdiff_t>(m) * stride, c.tail.end());
    b.margin_line.assign(c.tail_line.begin() + (held - m), c.tail_line.end());
  }
  int run_start = 0;  // first row of the block in the run that ends the block
  for (int i = 0; i < b.n; ++i) {
    const double* r = b.row(i);
    const double blk = r[plan.width + 1];
    const int line = b.line[i];
    if (!c.any || (blocks && blk != c.run_block)) {
      check_run(plan, *f, c);
      c.run_length = 0;
      c.run_first_line = line;
      c.run_block = blk;
      c.tail.clear();
      c.tail_line.clear();
      run_start = i;
    }
    ++c.run_length;
    c.any = true;
    c.last_line = line;
  }
  // The tail: the last `keep` rows of the current run.
  const int from = std::max(run_start, b.n - static_cast<int>(std::min<size_t>(keep, b.n)));
  c.tail.insert(c.tail.end(), b.rows.begin() + static_cast<std::ptrdiff_t>(from) * stride,
                b.rows.end());
  c.tail_line.insert(c.tail_line.end(), b.line.begin() + from, b.line.end());
  if (c.tail_line.size() > keep) {
    const size_t drop = c.tail_line.size() - keep;
    c.tail.erase(c.tail.begin(), c.tail.begin() + static_cast<std::ptrdiff_t>(drop) * stride);
    c.tail_line.erase(c.tail_line.begin(), c.tail_line.begin() + static_cast<std::ptrdiff_t>(drop));
  }
}

// The prepared samples of a sequenced block, in order: without the filter its
// rows; with it, filter_motion's output rows whose window ends in the block
// (the margin is pushed first, its outputs are the previous block's), then
// resolve_upstream as prepare_motion_samples runs it after the filter.
template <class Sink>
void prepared_rows(const MotionPlan& plan, const FilterPlan* f, const ParsedBlock& b, Sink&& sink) {
  const int W = plan.width;
  if (!f) {
    for (int i = 0; i < b.n; ++i) sink(unfiltered(plan, b.row(i), b.line[i]));
    return;
  }
  MotionFilter filter(f->kernels, W, plan.nd, f->decimation);
  filter.set_source(plan.cols.source);
  std::vector<double> value(W + 2), first(std::max(plan.nd, 1)), second(std::max(plan.nd, 1));
  double gravity[3], sensor[9];
  const bool blocks = plan.cols.block >= 0;
  // A quaternion of the sensor's pose is filtered with its sign continuous
  // from row to row, given rates with it (continue_pose_sign; the rates are
  // the same for either sign of the whole window): the rows pushed are copies.
  const bool signs = plan.up && plan.model && plan.model->pose != SensorPoseColumns::None;
  std::vector<double> pushed(signs ? W : 0), previous(signs ? 4 : 0);
  bool any = false;
  const auto push = [&](const double* r, int line) {
    if (signs) {
      std::copy_n(r, W, pushed.data());
      if (any)
        continue_pose_sign(plan.model->pose, previous.data(), pushed.data() + plan.o_qu,
                           plan.has_qdu ? pushed.data() + plan.o_qdu : nullptr,
                           plan.has_qdu ? pushed.data() + plan.o_qddu : nullptr);
      std::copy_n(pushed.data() + plan.o_qu, 4, previous.data());
      any = true;
      filter.push(pushed.data(), r[W], line);
    } else {
      filter.push(r, r[W], line);
    }
  };
  for (int i = 0; i < b.margin_rows; ++i) {
    const double* r = b.margin.data() + static_cast<size_t>(i) * plan.stride;
    push(r, b.margin_line[i]);
    filter.pop(nullptr, nullptr, nullptr, nullptr, nullptr);
  }
  for (int i = 0; i < b.n; ++i) {
    const double* r = b.row(i);
    if (i == 0 ? !b.continues : (blocks && r[W + 1] != b.row(i - 1)[W + 1])) filter.reset();
    push(r, b.line[i]);
    double t;
    int line;
    if (!filter.pop(value.data(), first.data(), second.data(), &t, &line)) continue;
    // The stored layout, with the derivatives the filter derives.
    FinalRow out = unfiltered(plan, value.data(), line);
    out.t = t;
    out.block = r[W + 1];
    if (plan.derive_q) {
      out.qd = first.data() + plan.d_q;
      out.qdd = second.data() + plan.d_q;
    }
    if (plan.derive_up) {
      out.qdu = first.data() + plan.d_qu;
      out.qddu = second.data() + plan.d_qu;
    }
    if (plan.post_resolve) {
      upstream_sensor_frame(*plan.model, out.qu, out.qdu, out.qddu, plan.cols.root_gravity,
                            plan.cols.gravity_from_upstream ? gravity : nullptr,
                            plan.post_moving ? sensor : nullptr);
      if (plan.cols.gravity_from_upstream) out.g = gravity;
      if (plan.post_moving) out.sm = sensor;
    }
    sink(out);
  }
}

// A run of rows of one block value (the whole log without a block column).
struct Run {
  long long length = 0;
  int first_line = 0, last_line = 0;
  double block = 0.0;
};

// filter_motion's error for a repeated or decreasing t.
struct OrderError {
  int line = 0, previous_line = 0;
  double t = 0.0, previous_t = 0.0;
  [[noreturn]] void raise(const std::string& source) const {
    if (t == previous_t)
      throw InputError(fmt::format("{}: t = {} repeats the time of line {} (t must increase)",
                                   where(source, line), t, previous_line));
    throw InputError(fmt::format("{}: t = {} is before t = {} of line {} (t must increase)",
                                 where(source, line), t, previous_t, previous_line));
  }
};

// Prepared rows collected into Samples (prepare_motion_samples' shape):
// add() copies a row (the filter reuses its buffers), take() the samples.
class SampleCollector {
 public:
  explicit SampleCollector(const MotionPlan& plan);
  void add(const FinalRow& r);
  // `source`: the samples' source; the flags and root gravity are the plan's.
  Samples take(const std::string& source);

 private:
  // One array of the samples: from a row's `from`, `n` values (0: none).
  struct Group {
    const double* FinalRow::*from;
    Eigen::MatrixXd Samples::*to;
    int n;
    std::vector<double> values;
  };
  const MotionPlan& plan_;
  int n_ = 0;
  std::vector<Group> groups_;
  std::vector<double> t_;
  std::vector<int> line_, block_;
};

// The SampleColumns of samples in memory, one row of values per sample in
// samples_row's layout: q, qd, qdd, q_upstream, qd_upstream, qdd_upstream,
// gravity, sensor motion, wrench (zeros when the samples have none), t, block.
SampleColumns columns_of(const Samples& samples);
void samples_row(const Samples& samples, const SampleColumns& cols, int i, double* v);

}  // namespace massid::detail

// Motion logs identified from CSV in constant memory (streaming.hpp,
// identify_motion_csv): blocks parsed on threads, the zero-phase filter of
// motion_filter.hpp applied block by block with the rows before it as a
// margin, the rows folded by IdentifyAccumulator (streaming_identify.cpp).
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "identify/motion_pipeline.hpp"
#include "identify/ordered_blocks.hpp"
#include "io/csv_stream.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/motion_filter.hpp"
#include "massid/identify/streaming.hpp"

namespace massid {

using detail::ordered_blocks;
using detail::thread_count;

// --------------------------------------------------------------- motion logs

namespace detail {
namespace {

std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// The t (and block) column alone, for the sample period: the columns bound
// as two values (t, block), so that parse_block reads and checks them as
// read_samples would (the other cells are skipped, their fields counted).
SampleColumns time_columns(const SampleColumns& cols) {
  SampleColumns tc = cols;
  tc.target.assign(cols.header.size(), -1);
  tc.scale.assign(cols.header.size(), 1.0);
  tc.column_of.clear();
  for (const int role : {cols.time, cols.block})
    if (role >= 0) {
      tc.target[cols.column_of[role]] = static_cast<int>(tc.column_of.size());
      tc.column_of.push_back(cols.column_of[role]);
    }
  tc.time = 0;
  tc.block = cols.block >= 0 ? 1 : -1;
  tc.num_values = static_cast<int>(tc.column_of.size());
  tc.gravity_from_force = tc.gravity_from_tilt = false;
  tc.gravity_from_upstream = false;
  tc.wrench = tc.gravity = 0;
  tc.qd = tc.qdd = tc.sensor = tc.q_up = tc.qd_up = tc.qdd_up = -1;
  return tc;
}

// The steps of t within runs as (bits, count) of their distinct values,
// while there are few (a log's time stamps are on a grid: a handful).
struct StepCounts {
  static constexpr size_t kMaxDistinct = 1 << 16;
  std::unordered_map<std::uint64_t, long long> count;
  bool overflow = false;
  long long total = 0;
  // n steps of the bit pattern `bits`.
  void add(std::uint64_t bits, long long n = 1) {
    total += n;
    if (overflow) return;
    count[bits] += n;
    if (count.size() > kMaxDistinct) {
      overflow = true;
      count.clear();
    }
  }
  void merge(const StepCounts& o) {
    if (o.overflow) {
      overflow = true;
      count.clear();
      total += o.total;
      return;
    }
    for (const auto& [b, n] : o.count) add(b, n);
  }
  // The step of rank total / 2 (nth_element's median); NaN when overflowed.
  double median() const {
    if (overflow || total == 0) return std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<std::uint64_t, long long>> v(count.begin(), count.end());
    std::sort(v.begin(), v.end());  // positive doubles order like their bits
    long long rank = total / 2;
    for (const auto& [b, n] : v) {
      if (rank < n) {
        double x;
        std::memcpy(&x, &b, sizeof x);
        return x;
      }
      rank -= n;
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
};

// One block of the scan of t: its runs (the first may continue the previous
// block's, the last the next's), its steps, the first order error in it.
struct TimePart {
  size_t lines = 0;
  long long rows = 0;
  double first_t = 0.0, last_t = 0.0;
  int first_line = 0, last_line = 0;  // relative to the block's first line
  std::vector<Run> runs;              // relative lines
  StepCounts steps;
  std::optional<OrderError> error;  // relative lines
};

// What filter_motion learns from t before it filters: the blocks' parts
// joined (absolute lines), and the median step within runs.
struct TimeScan : TimePart {
  double dt = std::numeric_limits<double>::quiet_NaN();
};

TimePart scan_time_block(std::string_view text, const SampleColumns& tc, size_t begin, size_t end) {
  TimePart part;
  const bool blocks = tc.block >= 0;
  try {
    part.lines = parse_block(text, tc, begin, end, [&](const double* v, size_t pos, int line) {
      const double t = v[0], b = blocks ? v[1] : 0.0;
      if (part.error) return;  // what follows the block's first error is not used
      if (blocks && !is_block_number(b)) throw_not_integer(text, pos, tc, b);
      if (part.rows > 0 && (!blocks || b == part.runs.back().block)) {
        if (!(t > part.last_t)) {
          part.error = OrderError{line, part.last_line, t, part.last_t};
          return;
        }
        part.steps.add(bits_of(t - part.last_t));
        Run& r = part.runs.back();
        ++r.length;
        r.last_line = line;
      } else {
        if (part.rows == 0) {
          part.first_t = t;
          part.first_line = line;
        }
        part.runs.push_back({1, line, line, b});
      }
      ++part.rows;
      part.last_t = t;
      part.last_line = line;
    });
  } catch (const InputError&) {
    if (!part.error) throw;  // (an error after the block's first is not its first)
  }
  return part;
}

// The exact median step when there are too many distinct steps to count:
// radix selection on their bits, one sequential pass over t per 16 bits
// until the candidates left fit in memory.
double radix_median_step(std::string_view text, const SampleColumns& tc, long long total) {
  const bool blocks = tc.block >= 0;
  const auto for_each_step = [&](auto&& use) {
    bool any = false;
    double last_t = 0.0, last_b = 0.0;
    parse_block(text, tc, tc.data_begin, text.size(), [&](const double* v, size_t) {
      const double t = v[0], b = blocks ? v[1] : 0.0;
      if (any && (!blocks || b == last_b)) use(t - last_t);
      any = true;
      last_t = t;
      last_b = b;
    });
  };
  constexpr int kDigit = 16;
  constexpr long long kCollect = 1 << 20;
  std::uint64_t prefix = 0;
  int known = 0;  // leading bits of the median's pattern known
  long long rank = total / 2;
  std::vector<long long> hist(std::size_t{1} << kDigit);
  const auto matches = [&](std::uint64_t b) {
    return known == 0 || (b >> (64 - known)) == (prefix >> (64 - known));
  };
  while (true) {
    const int shift = 64 - known - kDigit;
    std::fill(hist.begin(), hist.end(), 0);
    for_each_step([&](double s) {
      const std::uint64_t b = bits_of(s);
      if (matches(b)) ++hist[(b >> shift) & ((std::uint64_t{1} << kDigit) - 1)];
    });
    long long below = 0;
    std::size_t d = 0;
    while (d + 1 < hist.size() && below + hist[d] <= rank) below += hist[d++];
    prefix |= static_cast<std::uint64_t>(d) << shift;
    known += kDigit;
    rank -= below;
    if (known == 64) {
      double x;
      std::memcpy(&x, &prefix, sizeof x);
      return x;
    }
    if (hist[d] <= kCollect) {
      std::vector<double> left;
      for_each_step([&](double s) {
        if (matches(bits_of(s))) left.push_back(s);
      });
      std::nth_element(left.begin(), left.begin() + rank, left.end());
      return left[static_cast<std::size_t>(rank)];
    }
  }
}

// filter_motion's first look at t, over the whole file in parallel blocks:
// a repeated or decreasing t (the first in the file) is its error; the runs;
// the median step within runs, exactly.
TimeScan scan_log_times(const MappedFile& file, const MotionPlan& plan,
                        const StreamOptions& stream) {
  const std::string_view text = file.text();
  const SampleColumns tc = time_columns(plan.cols);
  const size_t bytes = std::max<size_t>(stream.block_bytes, 1);
  TimeScan out;
  int line_base = tc.header_line + 1;
  ordered_blocks<TimePart>(
      num_blocks(text, tc, bytes), thread_count(stream),
      [&](size_t k) {
        const auto [begin, end] = block_range(text, tc, bytes, k);
        TimePart part = scan_time_block(text, tc, begin, end);
        file.release(begin, end);
        return part;
      },
      [&](TimePart&& part) {
        const int base = line_base;
        line_base += static_cast<int>(part.lines);
        for (size_t i = 0; i < part.runs.size(); ++i) {
          Run r = part.runs[i];
          r.first_line += base;
          r.last_line += base;
          if (i == 0 && out.rows > 0 && r.block == out.runs.back().block) {
            // The run goes on from the previous block: the step between them.
            const double t = part.first_t;
            if (!(t > out.last_t))
              OrderError{r.first_line, out.last_line, t, out.last_t}.raise(tc.source);
            out.steps.add(bits_of(t - out.last_t));
            out.runs.back().length += r.length;
            out.runs.back().last_line = r.last_line;
          } else {
            out.runs.push_back(r);
          }
        }
        if (part.error) {
          OrderError e = *part.error;
          e.line += base;
          e.previous_line += base;
          e.raise(tc.source);
        }
        if (part.rows == 0) return;
        if (out.rows == 0) out.first_line = base + part.first_line;
        out.rows += part.rows;
        out.last_line = base + part.last_line;
        out.last_t = part.last_t;
        out.steps.merge(part.steps);
      });
  if (out.steps.total > 0)
    out.dt = out.steps.overflow ? radix_median_step(text, tc, out.steps.total) : out.steps.median();
  return out;
}

// A head assumption that the stream found wrong (they only ever turn one way).
struct AssumptionFailed {
  bool gravity_varies = false;
  bool sensor_moves = false;
};

// The head of the file: its rows, parsed until they hold a prepared sample
// (with the filter: until the first run holds `window` rows or ends), or the
// whole file.
struct Head {
  ParsedBlock rows;
  bool complete = false;  // the whole file
  size_t end = 0;         // byte offset after it
};

Head read_head(std::string_view text, const MotionPlan& plan, const StreamOptions& stream,
               int window) {
  const SampleColumns& c = plan.cols;
  std::size_t bytes = std::max<std::size_t>(stream.pilot_bytes, 1);
  while (true) {
    Head h;
    h.end = block_range(text, c, bytes, 0).second;
    h.complete = h.end >= text.size();
    h.rows = parse_rows(text, plan, c.data_begin, h.end);
    const ParsedBlock& b = h.rows;
    const int W = plan.width;
    int first_run = 0;  // the rows of the first run (window: 0 without the filter)
    while (first_run < b.n &&
           (first_run == 0 || c.block < 0 || b.row(first_run)[W + 1] == b.row(0)[W + 1]))
      ++first_run;
    if (h.complete || first_run < b.n || (b.n > 0 && first_run >= window)) return h;
    bytes *= 2;
  }
}

}  // namespace

}  // namespace detail

namespace {

// One streamed pass over a motion log: every block parsed, sequenced,
// prepared (filtered) and handed to a partial of type Part (an accumulator,
// or a ResidualMax), merged in block order. `check` sees every prepared row.
template <class Part, class Make, class Add, class Merge>
detail::Carry stream_motion(std::string_view text, const detail::MappedFile& file,
                            const detail::MotionPlan& plan, const FilterPlan* f,
                            const StreamOptions& stream, Make make, Add add, Merge merge) {
  using detail::ParsedBlock;
  const detail::SampleColumns& c = plan.cols;
  const size_t bytes = std::max<size_t>(stream.block_bytes, 1);
  const size_t blocks = detail::num_blocks(text, c, bytes);
  detail::Carry carry;
  carry.line_base = c.header_line + 1;
  // Parsed blocks, then their lines (with the filter: the margins) in order,
  // then prepared (filtered) on the threads. Row buffers are recycled.
  std::mutex pool_mutex;
  std::vector<std::vector<double>> pool;
  detail::ordered_pipeline<ParsedBlock, Part>(
      blocks, thread_count(stream),
      [&](size_t k) {
        const auto [begin, end] = detail::block_range(text, c, bytes, k);
        std::vector<double> storage;
        {
          const std::lock_guard<std::mutex> lock(pool_mutex);
          if (!pool.empty()) {
            storage = std::move(pool.back());
            pool.pop_back();
          }
        }
        ParsedBlock b = detail::parse_rows(text, plan, begin, end, std::move(storage));
        file.release(begin, end);
        return b;
      },
      [&](ParsedBlock& b) { detail::sequence_rows(plan, f, carry, b); },
      [&](ParsedBlock&& b) {
        Part part = make();
        detail::prepared_rows(plan, f, b, [&](const detail::FinalRow& r) { add(part, r); });
        const std::lock_guard<std::mutex> lock(pool_mutex);
        pool.push_back(std::move(b.rows));
        return part;
      },
      merge);
  if (f) detail::check_run(plan, *f, carry);
  return carry;
}

// Prepared samples kept for the largest residual while they fit in the
// budget (StreamOptions::keep_bytes; whether they all fit does not depend on
// timing, nor does the result): q, qd, qdd, g, sensor motion, w per sample.
class KeptSamples {
 public:
  // `reserve`: values to reserve for a block's samples (an estimate).
  KeptSamples(const detail::MotionPlan& plan, bool on, size_t budget, size_t reserve)
      : on_(on), budget_(budget), reserve_(reserve), plan_(plan), size_(sample_size(plan)) {}
  // Values a sample takes: q (qd, qdd), g, (sensor motion), w.
  static size_t sample_size(const detail::MotionPlan& plan) {
    return static_cast<size_t>(plan.nj) * (plan.final_qd ? 3 : 1) + 3 +
           (plan.final_sensor ? 9 : 0) + 6;
  }
  // Into a block's buffer (any thread).
  void store(const detail::FinalRow& r, std::vector<double>& to) {
    if (!on_ || overflow_.load(std::memory_order_relaxed)) return;
    if (to.capacity() == 0) to.reserve(reserve_);
    const size_t at = to.size();
    to.resize(at + size_);
    double* o = to.data() + at;
    const auto put = [&](const double* v, int n) {
      if (v) o = std::copy_n(v, n, o);  // (null: not in the log, sample_size)
    };
    put(r.q, plan_.nj);
    put(r.qd, plan_.nj);
    put(r.qdd, plan_.nj);
    put(r.g, 3);
    put(r.sm, 9);
    put(r.w, 6);
    if ((to.size() & 4095) < size_ &&
        used_.fetch_add(4096 * sizeof(double), std::memory_order_relaxed) > budget_)
      overflow_ = true;
  }
  // A block's samples (in block order).
  void append(std::vector<double>&& from) {
    if (overflow_) {
      blocks_.clear();
      return;
    }
    if (!from.empty()) blocks_.push_back(std::move(from));
  }
  bool complete() const { return on_ && !overflow_; }
  // (On the threads, block by block: a maximum is exact in any order.)
  Eigen::Matrix<double, 6, 1> residual_max(const Model& model, const BaseParameters& base,
                                           const Eigen::VectorXd& x, int threads) const {
    ResidualMax total(model, base, x);
    ordered_blocks<ResidualMax>(
        blocks_.size(), threads,
        [&](size_t k) {
          ResidualMax part(model, base, x);
          const std::vector<double>& rows = blocks_[k];
          const size_t g = static_cast<size_t>(plan_.nj) * (plan_.final_qd ? 3 : 1);
          const size_t w = g + 3 + (plan_.final_sensor ? 9 : 0);
          for (size_t i = 0; i < rows.size(); i += size_) {
            const double* v = rows.data() + i;
            part.add(MotionRow{v, plan_.final_qd ? v + plan_.nj : nullptr,
                               plan_.final_qd ? v + 2 * plan_.nj : nullptr, v + g,
                               plan_.final_sensor ? v + g + 3 : nullptr, v + w});
          }
          return part;
        },
        [&](ResidualMax&& part) { total.merge(part); });
    return total.max();
  }

 private:
  bool on_;
  size_t budget_, reserve_;
  const detail::MotionPlan& plan_;
  size_t size_;
  std::atomic<size_t> used_{0};
  std::atomic<bool> overflow_{false};
  std::vector<std::vector<double>> blocks_;
};

// Pilot rows from across a log without the filter: windows of 32 samples
// spread evenly over the file after the head, one per 4 MB (64 to 1024). A
// window that does not parse is left out (the stream reports the file's
// first error). The pages around a window (the kernel maps neighbours of a
// faulting page too) are released at once: the resident set stays small.
void add_spread_rows(const detail::MappedFile& file, const detail::MotionPlan& plan, size_t from,
                     IdentifyAccumulator& pilot) {
  const std::string_view text = file.text();
  constexpr int kRows = 32;
  const size_t size = text.size();
  if (from >= size) return;
  const size_t span = size - from;
  const int kWindows = static_cast<int>(std::clamp<size_t>(span >> 22, 64, 1024));
  const size_t window = std::max<size_t>(1, span / kWindows);
  for (int k = 0; k < kWindows; ++k) {
    const size_t at = from + window * static_cast<size_t>(k) + window / 2;
    if (at >= size) break;
    const void* nl = std::memchr(text.data() + at, '\n', size - at);
    if (!nl) break;
    size_t begin = static_cast<size_t>(static_cast<const char*>(nl) - text.data()) + 1, end = begin;
    for (int r = 0; r < kRows && end < size; ++r) {
      const void* e = std::memchr(text.data() + end, '\n', size - end);
      end = e ? static_cast<size_t>(static_cast<const char*>(e) - text.data()) + 1 : size;
    }
    try {
      const detail::ParsedBlock b = detail::parse_rows(text, plan, begin, end);
      for (int i = 0; i < b.n; ++i) pilot.add(detail::unfiltered(plan, b.row(i), 0).motion());
    } catch (const InputError&) {
    }
    constexpr size_t kAround = 256u << 10;
    file.release(begin > kAround ? (begin - kAround) / 4096 * 4096 : 0, end + kAround);
  }
}

}  // namespace

MotionIdentification identify_motion_csv(const Model& model, const std::string& path, bool offset,
                                         const IdentifyOptions& options,
                                         const MotionDataOptions& data,
                                         const StreamOptions& stream) {
  const detail::MappedFile file(path);
  const std::string_view text = file.text();
  const detail::MotionPlan plan(&model,
                                detail::bind_columns(model, text, path, data.samples, true));
  // The filter: what filter_motion learns from t first (order, runs, the
  // median step), from a scan of t alone, then its checks in its order.
  std::optional<FilterPlan> filter;
  if (plan.derived) {
    detail::require_time_column(path, plan.cols.time >= 0);
    const detail::TimeScan ts = detail::scan_log_times(file, plan, stream);
    detail::check_time_series(path, ts.rows, ts.steps.total, ts.first_line);
    filter = plan_filter(ts.dt, data.filter, plan.cols.source, ts.first_line, ts.last_line);
    for (const detail::Run& r : ts.runs)
      if (r.length < filter->kernels.size())
        detail::throw_short_run(plan, *filter, r.length, r.first_line, r.last_line, r.block);
  }
  const FilterPlan* f = filter ? &*filter : nullptr;

  // The head prepared: the log's first samples (the gravity motion_base_options
  // compares with; whether gravity varies or the sensor moves there), the
  // pilot estimate, the head returned.
  detail::Head head = detail::read_head(text, plan, stream, f ? f->kernels.size() : 0);
  detail::Carry head_carry;
  head_carry.line_base = plan.cols.header_line + 1;
  detail::sequence_rows(plan, f, head_carry, head.rows);
  detail::SampleCollector head_rows(plan);
  detail::prepared_rows(plan, f, head.rows, [&](const detail::FinalRow& r) { head_rows.add(r); });
  const Samples head_samples = head_rows.take(path);

  MotionIdentification out;
  // What the head shows (a fixed gravity, a sensor at rest) holds until a row
  // of the stream shows otherwise.
  BaseParameterOptions bo = motion_base_options(head_samples, offset);
  const Eigen::Vector3d g0 = bo.sensor_gravity;
  const double g_tolerance = detail::fixed_gravity_tolerance(g0);
  while (true) {
    try {
      out.base = find_base_parameters(model, bo);
      const BaseParameters& base = out.base;
      // The largest residual without a pass of its own: the prepared samples
      // kept while they fit in StreamOptions::keep_bytes (a filtered log
      // keeps one row in D), else candidate rows proven against a pilot
      // estimate from the head and, without the filter, from windows spread
      // over the file.
      const bool track = stream.residual_max && !head.complete;
      const size_t sample_bytes = sizeof(double) * KeptSamples::sample_size(plan);
      const double rows_per_byte =
          head.rows.n > 0 ? head.rows.n / static_cast<double>(head.end - plan.cols.data_begin) : 0;
      const double expected = rows_per_byte *
                              static_cast<double>(text.size() - plan.cols.data_begin) /
                              (f ? f->decimation : 1);
      const bool keep = head.complete || (track && expected * static_cast<double>(sample_bytes) <=
                                                       static_cast<double>(stream.keep_bytes));
      std::optional<Eigen::VectorXd> xhat;
      std::optional<IdentifyAccumulator> pilot;
      if (track && !keep && head_samples.size() > 0) {
        pilot.emplace(model, base);
        pilot->add(head_samples);
        if (!f) add_spread_rows(file, plan, head.end, *pilot);
        xhat = pilot->rough_estimate();
      }
      // (The partials are copies of a prototype that nothing changes.)
      IdentifyAccumulator prototype(model, base);
      prototype.set_source(path, plan.cols.gravity_from_force, plan.cols.gravity_from_upstream);
      if (f) prototype.set_noise_lags(correlated_rows(f->kernels, f->decimation));
      if (xhat) prototype.track_residuals(*xhat, &*pilot);
      const auto tracked = [&] { return prototype.empty_like(); };
      IdentifyAccumulator total = tracked();
      const double block_samples = rows_per_byte *
                                   static_cast<double>(std::max<size_t>(stream.block_bytes, 1)) /
                                   (f ? f->decimation : 1);
      // (The whole log in the head: every sample kept, whatever the budget.)
      KeptSamples kept(plan, keep,
                       head.complete ? std::numeric_limits<size_t>::max() : stream.keep_bytes,
                       static_cast<size_t>(std::min(1.1 * block_samples + 64, double{1 << 20})) *
                           KeptSamples::sample_size(plan));
      ++out.passes;
      // Every prepared row is checked against what the base assumes (a
      // fixed gravity: within motion_base_options' tolerance of the first
      // sample's; a sensor at rest); a row that is not starts over.
      struct Part {
        IdentifyAccumulator acc;
        std::vector<double> rows;  // kept samples
      };
      const detail::Carry carry = stream_motion<Part>(
          text, file, plan, f, stream,
          [&] {
            return Part{tracked(), {}};
          },
          [&](Part& part, const detail::FinalRow& r) {
            if (bo.fixed_gravity &&
                (Eigen::Map<const Eigen::Vector3d>(r.g) - g0).norm() > g_tolerance)
              throw detail::AssumptionFailed{true, false};
            if (!bo.sensor_moving && r.sm &&
                Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.sm).cwiseAbs().maxCoeff() > 0.0)
              throw detail::AssumptionFailed{false, true};
            part.acc.add(r.motion());
            kept.store(r, part.rows);
          },
          [&](Part&& part) {
            total.merge(std::move(part.acc));
            kept.append(std::move(part.rows));
          });
      out.summary = total.finish(options);
      out.report.rows = static_cast<int>(carry.rows);
      out.report.derived = plan.derived;
      if (f) {
        out.report.kernels = f->kernels;
        out.report.decimation = f->decimation;
      }
      out.head = head_samples;
      // The largest residual: from the kept samples (every one when the head
      // is the whole log), else proven by the tracked candidates, else a
      // pass of its own.
      if (kept.complete()) {
        out.summary.residual_max =
            kept.residual_max(model, base, out.summary.value, thread_count(stream));
      } else if (stream.residual_max && out.summary.residual_max.hasNaN()) {
        out.residual_pass = true;
        ResidualMax rmax(model, base, out.summary.value);
        stream_motion<ResidualMax>(
            text, file, plan, f, stream,
            [&] { return ResidualMax(model, base, out.summary.value); },
            [&](ResidualMax& part, const detail::FinalRow& r) { part.add(r.motion()); },
            [&](ResidualMax&& part) { rmax.merge(part); });
        out.summary.residual_max = rmax.max();
      }
      return out;
    } catch (const detail::AssumptionFailed& e) {
      // They only turn one way: at most two more passes.
      bo.fixed_gravity = bo.fixed_gravity && !e.gravity_varies;
      bo.sensor_moving = bo.sensor_moving || e.sensor_moves;
    }
  }
}

}  // namespace massid

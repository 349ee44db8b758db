// Streaming identification (streaming.hpp): per-axis triangular factors folded
// chunk by chunk, merged in a fixed order, solved like identify() does.
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "csv_stream.hpp"
#include "householder_fold.hpp"
#include "massid/errors.hpp"
#include "massid/identifiability.hpp"
#include "massid/regressor.hpp"
#include "massid/streaming.hpp"
#include "stream_regressor.hpp"

namespace massid {
namespace detail {

// Rows per chunk folded at once into R_a. 128 rows x 16 columns of doubles is
// 16 KB per moment axis: the chunk stays in L1/L2 while it is reduced, and the
// per-chunk overhead (the n x n triangle's rows) is small against 2 m n^2.
constexpr int kChunk = 128;

// --------------------------------------------------------------- accumulator

struct Axis {
  int n = 0;                 // columns: unknowns, then y
  std::vector<int> unknown;  // [n - 1] unknown index of each column
  Eigen::MatrixXd R;         // [n x n] upper triangular
  Eigen::MatrixXd B;         // [kChunk x n] rows not yet folded
};

struct AccumulatorState {
  const Model* model;
  const BaseParameters* base;
  StreamRegressor reg;
  std::array<Axis, 6> axes;
  int pending = 0;
  long long count = 0;
  // The pending rows' samples, a column of kChunk per value: q (joint j at
  // j * kChunk), g, w. Their regressor rows are computed a chunk at a time.
  std::vector<double> qbuf, gbuf, wbuf;
  // The first `keep` samples and the joint ranges, for the identifiability
  // diagnosis (check_identifiability re-tests the data's first max(3p, 30)
  // samples with perturbed poses, and names joints that never move).
  int keep = 0;
  std::vector<double> kept_q, kept_g;
  std::vector<int> kept_line;
  std::vector<double> qmin, qmax;
  std::string source = "<samples>";
  bool gravity_from_force = false;

  // Largest residual without a second pass (see track_residuals): with a
  // provisional estimate xhat, each axis keeps the kCandidates rows of largest
  // |y - a xhat| (q, g, w), `dropped` bounds |y - a xhat| of every other row,
  // and `anorm2` is the largest |a|^2 of the axis' regressor rows. Once x is
  // known, a dropped row's residual is at most dropped + |a| |x - xhat|.
  static constexpr int kCandidates = 64;
  struct Candidate {
    double value;
    std::vector<double> row;  // q, g, w
  };
  bool track = false;
  Eigen::VectorXd xhat;
  std::array<std::vector<Candidate>, 6> candidates;
  std::array<double, 6> dropped{}, anorm2{}, admit{};
  std::vector<double> pred, norm2;  // [kChunk] scratch of track_rows

  AccumulatorState(const Model& m, const BaseParameters& b)
      : model(&m),
        base(&b),
        reg(m, b, kChunk),
        qbuf(static_cast<size_t>(m.num_joints()) * kChunk),
        gbuf(3 * kChunk),
        wbuf(6 * kChunk) {
    const int off = b.offset ? 1 : 0;
    for (int a = 0; a < 6; ++a) {
      Axis& ax = axes[a];
      if (a < 3) {
        ax.unknown.push_back(b.total_mass);
      } else {
        ax.unknown = reg.unknown();
      }
      if (off) ax.unknown.push_back(b.num_mass() + a);
      ax.n = static_cast<int>(ax.unknown.size()) + 1;
      ax.R = Eigen::MatrixXd::Zero(ax.n, ax.n);
      ax.B.resize(kChunk, ax.n);
    }
    keep = 8 * b.num_unknowns() + 64;
    admit.fill(-1.0);
    dropped.fill(-1.0);  // -1: no row dropped
    qmin.assign(m.num_joints(), std::numeric_limits<double>::infinity());
    qmax.assign(m.num_joints(), -std::numeric_limits<double>::infinity());
  }

  // Folds the pending rows: their regressor rows (force axes: g, 1, w; moment
  // axes: the moment rows, 1, w) into the axes' B, then B into R.
  void flush() {
    if (pending == 0) return;
    const int m = pending, K = reg.size();
    const bool off = base->offset;
    for (int a = 0; a < 6; ++a) {
      Axis& ax = axes[a];
      double* B = ax.B.data();
      const double* src = a < 3 ? gbuf.data() + a * kChunk : nullptr;
      const int first = a < 3 ? 1 : K;  // columns before the offset's
      for (int r = 0; r < m; ++r) {
        if (src) B[r] = src[r];
        if (off) B[first * kChunk + r] = 1.0;
        B[(ax.n - 1) * kChunk + r] = wbuf[a * kChunk + r];
      }
    }
    double* const out[3] = {axes[3].B.data(), axes[4].B.data(), axes[5].B.data()};
    reg.compute(m, qbuf.data(), gbuf.data(), kChunk, out, kChunk);
    if (track) track_rows(m);
    for (Axis& ax : axes) fold_rows(ax.R.data(), ax.n, ax.B.data(), m, kChunk);
    pending = 0;
  }

  void add(const double* q, const double* g, const double* w, int line) {
    const int r = pending;
    const int nj = reg.num_joints();
    for (int j = 0; j < nj; ++j) qbuf[j * kChunk + r] = q[j];
    for (int k = 0; k < 3; ++k) gbuf[k * kChunk + r] = g[k];
    for (int k = 0; k < 6; ++k) wbuf[k * kChunk + r] = w[k];
    if (++pending == kChunk) flush();
    if (count < keep) {
      kept_q.insert(kept_q.end(), q, q + nj);
      kept_g.insert(kept_g.end(), g, g + 3);
      kept_line.push_back(line);
    }
    for (int j = 0; j < nj; ++j) {
      qmin[j] = std::min(qmin[j], q[j]);
      qmax[j] = std::max(qmax[j], q[j]);
    }
    ++count;
  }

  void track_residuals(const Eigen::VectorXd& estimate) {
    track = true;
    xhat = estimate;
  }

  // Keeps the kCandidates largest, ties in row order (stable); the others
  // raise `dropped`.
  void prune(int a) {
    auto& c = candidates[a];
    std::stable_sort(c.begin(), c.end(),
                     [](const Candidate& x, const Candidate& y) { return x.value > y.value; });
    if (static_cast<int>(c.size()) > kCandidates) {
      dropped[a] = std::max(dropped[a], c[kCandidates].value);
      c.resize(kCandidates);
    }
    admit[a] = static_cast<int>(c.size()) == kCandidates ? c.back().value : -1.0;
  }

  // The residuals at xhat of the m pending rows, whose regressor rows are in
  // the axes' B (before folding), in row order.
  void track_rows(int m) {
    pred.resize(kChunk);
    norm2.resize(kChunk);
    const double* x = xhat.data();
    const int nj = reg.num_joints();
    for (int a = 0; a < 6; ++a) {
      // pred = A_a xhat, norm2 = |row of A_a|^2, column by column (over rows r).
      const Axis& ax = axes[a];
      for (int r = 0; r < m; ++r) pred[r] = norm2[r] = 0.0;
      for (int c = 0; c + 1 < ax.n; ++c) {
        const double* col = ax.B.data() + c * kChunk;
        const double xc = x[ax.unknown[c]];
        for (int r = 0; r < m; ++r) {
          pred[r] += col[r] * xc;
          norm2[r] += col[r] * col[r];
        }
      }
      const double* y = ax.B.data() + (ax.n - 1) * kChunk;
      for (int r = 0; r < m; ++r) {
        anorm2[a] = std::max(anorm2[a], norm2[r]);
        const double value = std::abs(y[r] - pred[r]);
        if (value <= admit[a]) {
          dropped[a] = std::max(dropped[a], value);
          continue;
        }
        Candidate c{value, {}};
        c.row.resize(nj + 9);
        for (int j = 0; j < nj; ++j) c.row[j] = qbuf[j * kChunk + r];
        for (int k = 0; k < 3; ++k) c.row[nj + k] = gbuf[k * kChunk + r];
        for (int k = 0; k < 6; ++k) c.row[nj + 3 + k] = wbuf[k * kChunk + r];
        candidates[a].push_back(std::move(c));
        if (static_cast<int>(candidates[a].size()) >= 2 * kCandidates) prune(a);
      }
    }
  }

  // Appends `later`'s rows (both are flushed first).
  void merge(AccumulatorState& later) {
    later.flush();
    flush();
    if (later.count == 0) return;
    for (int a = 0; a < 6; ++a) {
      Axis& ax = axes[a];
      if (count == 0) {
        ax.R = later.axes[a].R;
      } else {
        Eigen::MatrixXd B = later.axes[a].R;
        fold_rows(ax.R.data(), ax.n, B.data(), ax.n, ax.n);
      }
    }
    const int nj = reg.num_joints();
    for (size_t i = 0; i < later.kept_line.size() && static_cast<int>(kept_line.size()) < keep;
         ++i) {
      kept_q.insert(kept_q.end(), later.kept_q.begin() + i * nj,
                    later.kept_q.begin() + (i + 1) * nj);
      kept_g.insert(kept_g.end(), later.kept_g.begin() + 3 * i, later.kept_g.begin() + 3 * i + 3);
      kept_line.push_back(later.kept_line[i]);
    }
    count += later.count;
    if (track) {
      for (int a = 0; a < 6; ++a) {
        for (auto& c : later.candidates[a]) candidates[a].push_back(std::move(c));
        dropped[a] = std::max(dropped[a], later.dropped[a]);
        anorm2[a] = std::max(anorm2[a], later.anorm2[a]);
        prune(a);
      }
    }
    for (int j = 0; j < nj; ++j) {
      qmin[j] = std::min(qmin[j], later.qmin[j]);
      qmax[j] = std::max(qmax[j], later.qmax[j]);
    }
  }
};

}  // namespace detail

namespace {

using detail::AccumulatorState;

int thread_count(const StreamOptions& stream) {
  if (stream.threads > 0) return stream.threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

// Runs make(k) for the blocks k = 0 .. num_blocks - 1 on `threads` threads and
// hands the results to consume() one at a time in block order, so that the
// result does not depend on the number of threads or on timing. At most
// 4 * threads blocks are ahead of the one awaited (bounded memory). When a
// block throws, later blocks are skipped and, once every thread has stopped,
// the exception of the lowest failing block (the first error in the data) is
// rethrown.
template <class Partial, class Make, class Consume>
void ordered_blocks(size_t num_blocks, int threads, Make make, Consume consume) {
  if (threads <= 1 || num_blocks <= 1) {
    for (size_t k = 0; k < num_blocks; ++k) consume(make(k));
    return;
  }
  std::mutex mu;
  std::condition_variable cv;
  size_t next_claim = 0, next_consume = 0;
  size_t error_block = std::numeric_limits<size_t>::max();
  std::exception_ptr error;
  bool consuming = false;
  std::map<size_t, Partial> ready;
  const size_t ahead = 4 * static_cast<size_t>(threads);

  auto worker = [&] {
    while (true) {
      size_t k;
      {
        std::unique_lock<std::mutex> lock(mu);
        cv.wait(lock, [&] {
          return next_claim >= num_blocks || next_claim > error_block ||
                 next_claim < next_consume + ahead;
        });
        if (next_claim >= num_blocks || next_claim > error_block) return;
        k = next_claim++;
      }
      std::optional<Partial> part;
      std::exception_ptr failure;
      try {
        part.emplace(make(k));
      } catch (...) {
        failure = std::current_exception();
      }
      std::unique_lock<std::mutex> lock(mu);
      if (failure) {
        if (k < error_block) {
          error_block = k;
          error = failure;
        }
        cv.notify_all();
        continue;
      }
      ready.emplace(k, std::move(*part));
      while (!consuming && !ready.empty() && ready.begin()->first == next_consume &&
             next_consume < error_block) {
        consuming = true;
        auto node = ready.extract(ready.begin());
        lock.unlock();
        std::exception_ptr consume_failure;
        try {
          consume(std::move(node.mapped()));
        } catch (...) {
          consume_failure = std::current_exception();
        }
        lock.lock();
        consuming = false;
        if (consume_failure && next_consume < error_block) {
          error_block = next_consume;
          error = consume_failure;
        }
        ++next_consume;
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

using Vector6d = Eigen::Matrix<double, 6, 1>;

constexpr size_t kPilotBytes = 2u << 20;

}  // namespace

// --------------------------------------------------------------- IdentifyAccumulator

IdentifyAccumulator::IdentifyAccumulator(const Model& model, const BaseParameters& base)
    : state_(std::make_unique<AccumulatorState>(model, base)) {}
IdentifyAccumulator::~IdentifyAccumulator() = default;
IdentifyAccumulator::IdentifyAccumulator(IdentifyAccumulator&&) noexcept = default;
IdentifyAccumulator& IdentifyAccumulator::operator=(IdentifyAccumulator&&) noexcept = default;

void IdentifyAccumulator::add(const double* q, const double* gravity, const double* wrench,
                              int line) {
  state_->add(q, gravity, wrench, line);
}

void IdentifyAccumulator::add(const Samples& samples) {
  if (!samples.has_wrench())
    throw InputError(samples.source + ": no measured wrench (columns fx,fy,fz,mx,my,mz)");
  std::vector<double> q(samples.q.cols());
  for (int i = 0; i < samples.size(); ++i) {
    for (size_t j = 0; j < q.size(); ++j) q[j] = samples.q(i, static_cast<Eigen::Index>(j));
    const Eigen::Vector3d g = samples.gravity.row(i).transpose();
    const Vector6d w = samples.wrench.row(i).transpose();
    state_->add(q.data(), g.data(), w.data(),
                i < static_cast<int>(samples.line.size()) ? samples.line[i] : 0);
  }
}

void IdentifyAccumulator::merge(IdentifyAccumulator&& later) { state_->merge(*later.state_); }

void IdentifyAccumulator::track_residuals(const Eigen::VectorXd& estimate) {
  state_->track_residuals(estimate);
}

Eigen::VectorXd IdentifyAccumulator::rough_estimate() const {
  AccumulatorState st = *state_;  // the pending rows folded in (a copy: this is const)
  st.flush();
  const int p = st.base->num_unknowns();
  std::array<Eigen::MatrixXd, 6> R;
  for (int a = 0; a < 6; ++a) R[a] = st.axes[a].R;
  int rows = 0;
  for (const auto& ax : st.axes) rows += ax.n;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, p);
  Eigen::VectorXd y(rows);
  for (int a = 0, r0 = 0; a < 6; ++a) {
    const detail::Axis& ax = st.axes[a];
    for (int i = 0; i < ax.n; ++i) {
      for (int j = i; j < ax.n - 1; ++j) A(r0 + i, ax.unknown[j]) = R[a](i, j);
      y[r0 + i] = R[a](i, ax.n - 1);
    }
    r0 += ax.n;
  }
  Eigen::VectorXd scale(p);
  for (int c = 0; c < p; ++c) {
    const double n = A.col(c).norm();
    scale[c] = n > 0 ? 1.0 / n : 1.0;
  }
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A * scale.asDiagonal());
  return scale.asDiagonal() * cod.solve(y);
}

long long IdentifyAccumulator::samples() const { return state_->count; }

void IdentifyAccumulator::set_source(const std::string& source, bool gravity_from_force) {
  state_->source = source;
  state_->gravity_from_force = gravity_from_force;
}
bool IdentifyAccumulator::gravity_from_force() const { return state_->gravity_from_force; }
const std::string& IdentifyAccumulator::source() const { return state_->source; }

IdentifySummary IdentifyAccumulator::finish(const IdentifyOptions& options) const {
  // The pending rows folded in (and tracked), on a copy: finish is const.
  AccumulatorState flushed = *state_;
  flushed.flush();
  const AccumulatorState& st = flushed;
  const BaseParameters& base = *st.base;
  const Model& model = *st.model;
  const long long N = st.count;
  const int p = base.num_unknowns();

  // Same checks, same order and messages as identify().
  if (base.offset && st.gravity_from_force)
    throw IdentifiabilityError(
        st.source +
        ": the sensor offsets cannot be estimated when gravity is taken from the measured force "
        "(no gx,gy,gz columns): a force offset would bend the gravity direction. Add gx,gy,gz "
        "columns, or identify without --offset.");
  if (6 * N < p)
    throw IdentifiabilityError(st.source + ": " + std::to_string(N) +
                               " samples give fewer equations than the " + std::to_string(p) +
                               " unknowns; record more poses");

  std::array<Eigen::MatrixXd, 6> R;
  for (int a = 0; a < 6; ++a) R[a] = st.axes[a].R;

  // G: the six R_a over the unknowns, stacked; G^T G = A^T A.
  int rows = 0;
  for (const auto& ax : st.axes) rows += ax.n - 1;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(rows, p);
  for (int a = 0, r0 = 0; a < 6; ++a) {
    const detail::Axis& ax = st.axes[a];
    for (int i = 0; i < ax.n - 1; ++i)
      for (int j = i; j < ax.n - 1; ++j) G(r0 + i, ax.unknown[j]) = R[a](i, j);
    r0 += ax.n - 1;
  }

  // Identifiability on G, which has the singular values (and right singular
  // vectors) of the stacked regressor. The perturbed-pose hints need samples:
  // the first `keep` ones (check_identifiability uses the first max(3p, 30)),
  // and, when there are more, two rows holding each joint's minimum and
  // maximum so that "JOINT never moves" is judged on all the data.
  {
    const int nj = model.num_joints();
    const int kept = static_cast<int>(st.kept_line.size());
    const int extra = N > kept ? 2 : 0;
    Samples sub;
    sub.source = st.source;
    sub.gravity_from_force = st.gravity_from_force;
    sub.q.resize(kept + extra, nj);
    sub.gravity.resize(kept + extra, 3);
    sub.line = st.kept_line;
    for (int i = 0; i < kept; ++i) {
      for (int j = 0; j < nj; ++j) sub.q(i, j) = st.kept_q[static_cast<size_t>(i) * nj + j];
      for (int k = 0; k < 3; ++k) sub.gravity(i, k) = st.kept_g[3 * static_cast<size_t>(i) + k];
    }
    for (int e = 0; e < extra; ++e) {
      for (int j = 0; j < nj; ++j) sub.q(kept + e, j) = e == 0 ? st.qmin[j] : st.qmax[j];
      sub.gravity.row(kept + e) = sub.gravity.row(0);
      sub.line.push_back(0);
    }
    const IdentifiabilityReport report =
        check_identifiability(model, base, sub, G, options.rank_tolerance);
    if (!report.ok()) {
      std::string message = report.message;
      const std::string said =
          st.source + ": the " + std::to_string(sub.size()) + " samples determine only";
      if (sub.size() != N && message.starts_with(said))
        message = st.source + ": the " + std::to_string(N) + " samples determine only" +
                  message.substr(said.size());
      throw IdentifiabilityError(message);
    }
  }

  IdentifySummary out;
  out.samples = static_cast<int>(N);
  out.gravity_from_force = st.gravity_from_force;
  out.sigma_estimated = !options.sigma_force || !options.sigma_moment;

  Eigen::VectorXd scale(p);
  for (int c = 0; c < p; ++c) scale[c] = 1.0 / G.col(c).norm();

  Vector6d sigma;
  for (int k = 0; k < 6; ++k) {
    const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
    sigma[k] = user ? *user : 1.0;
  }
  // |y_a|^2 is the squared norm of R_a's y column.
  double signal[2] = {0.0, 0.0};
  for (int a = 0; a < 6; ++a)
    signal[a / 3] += R[a].col(st.axes[a].n - 1).squaredNorm() / (3.0 * static_cast<double>(N));

  int wrows = 0;
  for (const auto& ax : st.axes) wrows += ax.n;
  const int iterations = out.sigma_estimated ? std::max(1, options.weight_iterations) : 1;
  Eigen::VectorXd x(p);
  Eigen::MatrixXd Rinv;
  Vector6d ssr;
  for (int it = 0; it < iterations; ++it) {
    // The weighted, column-scaled problem: QR of the stacked [R_a S, R_a y] / sigma_a.
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(wrows, p + 1);
    for (int a = 0, r0 = 0; a < 6; ++a) {
      const detail::Axis& ax = st.axes[a];
      for (int i = 0; i < ax.n; ++i) {
        for (int j = i; j < ax.n - 1; ++j)
          W(r0 + i, ax.unknown[j]) = R[a](i, j) * scale[ax.unknown[j]] / sigma[a];
        W(r0 + i, p) = R[a](i, ax.n - 1) / sigma[a];
      }
      r0 += ax.n;
    }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
    const Eigen::MatrixXd Rw = qr.matrixQR().topRows(p + 1).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd Rp = Rw.topLeftCorner(p, p);
    const Eigen::VectorXd xs = Rp.triangularView<Eigen::Upper>().solve(Rw.col(p).head(p));
    x = scale.asDiagonal() * xs;
    Rinv = Rp.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p));
    // SSR_a = |A_a x - y_a|^2 = |R_a [x_a; -1]|^2.
    for (int a = 0; a < 6; ++a) {
      const detail::Axis& ax = st.axes[a];
      Eigen::VectorXd xa(ax.n);
      for (int j = 0; j < ax.n - 1; ++j) xa[j] = x[ax.unknown[j]];
      xa[ax.n - 1] = -1.0;
      ssr[a] = (R[a].triangularView<Eigen::Upper>() * xa).squaredNorm();
    }
    if (!out.sigma_estimated) break;
    const double dof = std::max(1.0, static_cast<double>(N) - p / 6.0);
    for (int k = 0; k < 6; ++k) {
      const auto& user = k < 3 ? options.sigma_force : options.sigma_moment;
      if (user) continue;
      const double floor = 1e-13 * std::sqrt(signal[k / 3]) + 1e-150;
      sigma[k] = std::max(std::sqrt(ssr[k] / dof), floor);
    }
  }

  out.value = x;
  out.sigma = sigma;
  out.covariance = scale.asDiagonal() * (Rinv * Rinv.transpose()) * scale.asDiagonal();
  out.stddev = out.covariance.diagonal().cwiseSqrt();
  double chi2 = 0.0;
  for (int k = 0; k < 6; ++k) {
    chi2 += ssr[k] / (sigma[k] * sigma[k]);
    out.residual_rms[k] = std::sqrt(ssr[k] / static_cast<double>(N));
  }
  out.residual_max.setConstant(std::numeric_limits<double>::quiet_NaN());
  if (st.track) {
    // The exact residuals of the candidate rows (as residual_max_csv computes
    // them); the maximum is proven when no dropped row can exceed it.
    ResidualMax exact(model, base, x);
    const int nj = model.num_joints();
    for (const auto& axis : st.candidates)
      for (const auto& c : axis) exact.add(c.row.data(), c.row.data() + nj, c.row.data() + nj + 3);
    const Vector6d M = exact.max();
    bool proven = true;
    for (int a = 0; a < 6; ++a) {
      if (st.dropped[a] < 0) continue;  // every row is a candidate
      double d2 = 0.0;
      for (int u : st.axes[a].unknown) d2 += (x[u] - st.xhat[u]) * (x[u] - st.xhat[u]);
      const double bound = std::sqrt(st.anorm2[a] * d2);
      proven = proven && st.dropped[a] + 1.001 * bound + 1e-9 * M[a] < M[a];
    }
    if (proven) out.residual_max = M;
  }
  out.chi2_per_dof = 6 * N > p ? chi2 / static_cast<double>(6 * N - p) : 0.0;

  // eq. 36: the moment axes' R_a over the moment unknowns, stacked, have the
  // singular values of the stacked moment rows.
  std::vector<int> position(p, -1);
  int mcols = 0;
  for (int c = 0; c < p; ++c)
    if (base.is_moment_unknown(c)) position[c] = mcols++;
  if (mcols == 0) {
    out.condition_number = 1.0;
  } else {
    int mrows = 0;
    for (int a = 3; a < 6; ++a) mrows += st.axes[a].n - 1;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(mrows, mcols);
    for (int a = 3, r0 = 0; a < 6; ++a) {
      const detail::Axis& ax = st.axes[a];
      for (int i = 0; i < ax.n - 1; ++i)
        for (int j = i; j < ax.n - 1; ++j) M(r0 + i, position[ax.unknown[j]]) = R[a](i, j);
      r0 += ax.n - 1;
    }
    Eigen::MatrixXd Rm = M;
    if (M.rows() > M.cols()) {
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
      Rm = qr.matrixQR().topRows(M.cols()).triangularView<Eigen::Upper>();
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Rm);
    const auto& s = svd.singularValues();
    out.condition_number = s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
  }
  return out;
}

// --------------------------------------------------------------- ResidualMax

namespace detail {

// ResidualMax's samples are buffered like the accumulator's and evaluated a
// chunk at a time (StreamRegressor is a batch kernel).
struct ResidualMaxState {
  StreamRegressor reg;
  Eigen::VectorXd value;
  Vector6d max = Vector6d::Zero();
  int total_mass = 0;
  int offset = -1;  // first offset unknown, -1 without offsets
  int pending = 0;
  std::vector<double> qbuf, gbuf, wbuf, moment;  // [values x kChunk], moment [3 K x kChunk]

  ResidualMaxState(const Model& model, const BaseParameters& base, const Eigen::VectorXd& x)
      : reg(model, base, kChunk),
        value(x),
        total_mass(base.total_mass),
        offset(base.offset ? base.num_mass() : -1),
        qbuf(static_cast<size_t>(model.num_joints()) * kChunk),
        gbuf(3 * kChunk),
        wbuf(6 * kChunk),
        moment(3 * static_cast<size_t>(reg.size()) * kChunk) {}

  void flush() {
    if (pending == 0) return;
    const int m = pending, K = reg.size();
    double* const out[3] = {moment.data(), moment.data() + static_cast<size_t>(K) * kChunk,
                            moment.data() + 2 * static_cast<size_t>(K) * kChunk};
    reg.compute(m, qbuf.data(), gbuf.data(), kChunk, out, kChunk);
    const double* x = value.data();
    for (int r = 0; r < m; ++r) {
      for (int a = 0; a < 3; ++a) {
        double pred = gbuf[a * kChunk + r] * x[total_mass];
        if (offset >= 0) pred += x[offset + a];
        max[a] = std::max(max[a], std::abs(wbuf[a * kChunk + r] - pred));
      }
      for (int a = 0; a < 3; ++a) {
        const double* mr = out[a] + r;
        double pred = 0.0;
        for (int i = 0; i < K; ++i) pred += mr[i * kChunk] * x[reg.unknown()[i]];
        if (offset >= 0) pred += x[offset + 3 + a];
        max[3 + a] = std::max(max[3 + a], std::abs(wbuf[(3 + a) * kChunk + r] - pred));
      }
    }
    pending = 0;
  }
};

}  // namespace detail

ResidualMax::ResidualMax(const Model& model, const BaseParameters& base,
                         const Eigen::VectorXd& value)
    : state_(std::make_unique<detail::ResidualMaxState>(model, base, value)) {}
ResidualMax::~ResidualMax() = default;
ResidualMax::ResidualMax(ResidualMax&&) noexcept = default;

void ResidualMax::add(const double* q, const double* gravity, const double* wrench) {
  detail::ResidualMaxState& st = *state_;
  const int r = st.pending, nj = st.reg.num_joints();
  for (int j = 0; j < nj; ++j) st.qbuf[j * detail::kChunk + r] = q[j];
  for (int k = 0; k < 3; ++k) st.gbuf[k * detail::kChunk + r] = gravity[k];
  for (int k = 0; k < 6; ++k) st.wbuf[k * detail::kChunk + r] = wrench[k];
  if (++st.pending == detail::kChunk) st.flush();
}

void ResidualMax::merge(const ResidualMax& other) {
  other.state_->flush();
  state_->flush();
  state_->max = state_->max.cwiseMax(other.state_->max);
}

// (Evaluates the samples still buffered: logically const.)
Eigen::Matrix<double, 6, 1> ResidualMax::max() const {
  state_->flush();
  return state_->max;
}

// --------------------------------------------------------------- drivers

IdentifySummary identify_streaming(const Model& model, const BaseParameters& base,
                                   const Samples& samples, const IdentifyOptions& options,
                                   const StreamOptions& stream) {
  if (!samples.has_wrench())
    throw InputError(samples.source + ": no measured wrench (columns fx,fy,fz,mx,my,mz)");
  const size_t N = static_cast<size_t>(samples.size());
  const size_t rows = static_cast<size_t>(std::max(1, stream.block_rows));
  const size_t blocks = (N + rows - 1) / rows;
  const int nj = model.num_joints();
  auto row = [&](size_t i, double* q, double* g, double* w) {
    for (int j = 0; j < nj; ++j) q[j] = samples.q(static_cast<Eigen::Index>(i), j);
    for (int k = 0; k < 3; ++k) g[k] = samples.gravity(static_cast<Eigen::Index>(i), k);
    for (int k = 0; k < 6; ++k) w[k] = samples.wrench(static_cast<Eigen::Index>(i), k);
  };
  IdentifyAccumulator total(model, base);
  total.set_source(samples.source, samples.gravity_from_force);
  ordered_blocks<IdentifyAccumulator>(
      blocks, thread_count(stream),
      [&](size_t k) {
        IdentifyAccumulator acc(model, base);
        std::vector<double> q(nj);
        double g[3], w[6];
        for (size_t i = k * rows; i < std::min(N, (k + 1) * rows); ++i) {
          row(i, q.data(), g, w);
          acc.add(q.data(), g, w,
                  i < samples.line.size() ? samples.line[i] : static_cast<int>(i) + 1);
        }
        return acc;
      },
      [&](IdentifyAccumulator&& acc) { total.merge(std::move(acc)); });
  IdentifySummary out = total.finish(options);
  if (stream.residual_max) {
    ResidualMax rmax(model, base, out.value);
    ordered_blocks<ResidualMax>(
        blocks, thread_count(stream),
        [&](size_t k) {
          ResidualMax part(model, base, out.value);
          std::vector<double> q(nj);
          double g[3], w[6];
          for (size_t i = k * rows; i < std::min(N, (k + 1) * rows); ++i) {
            row(i, q.data(), g, w);
            part.add(q.data(), g, w);
          }
          return part;
        },
        [&](ResidualMax&& part) { rmax.merge(part); });
    out.residual_max = rmax.max();
  }
  return out;
}

IdentifyAccumulator accumulate_csv(const Model& model, const BaseParameters& base,
                                   const std::string& path, const StreamOptions& stream,
                                   double g0) {
  const detail::MappedFile file(path);
  const std::string_view text = file.text();
  const detail::SampleColumns cols = detail::bind_columns(model, text, path, g0);
  const size_t bytes = std::max<size_t>(stream.block_bytes, 1);
  IdentifyAccumulator total(model, base);
  total.set_source(path, cols.gravity_from_force);
  const int w = cols.wrench_value(), g = cols.gravity_value();
  // The largest residual in the same pass: a provisional estimate from the
  // rows of the first 2 MB (a pilot, read twice) selects candidate rows, and
  // finish() proves the maximum from them (else it stays NaN and a second pass
  // is needed). Files within the pilot are cheap to read twice anyway.
  std::optional<Eigen::VectorXd> xhat;
  if (stream.residual_max) {
    const size_t pilot_end = detail::block_range(text, cols, kPilotBytes, 0).second;
    if (pilot_end < text.size()) {
      IdentifyAccumulator pilot(model, base);
      detail::parse_block(text, cols, cols.data_begin, pilot_end,
                          [&](const double* v, size_t) { pilot.add(v, v + g, v + w); });
      xhat = pilot.rough_estimate();
      total.track_residuals(*xhat);
    }
  }
  ordered_blocks<IdentifyAccumulator>(
      detail::num_blocks(text, cols, bytes), thread_count(stream),
      [&](size_t k) {
        const auto [begin, end] = detail::block_range(text, cols, bytes, k);
        IdentifyAccumulator acc(model, base);
        if (xhat) acc.track_residuals(*xhat);
        detail::parse_block(text, cols, begin, end,
                            [&](const double* v, size_t) { acc.add(v, v + g, v + w); });
        file.release(begin, end);
        return acc;
      },
      [&](IdentifyAccumulator&& acc) { total.merge(std::move(acc)); });
  return total;
}

Eigen::Matrix<double, 6, 1> residual_max_csv(const Model& model, const BaseParameters& base,
                                             const std::string& path, const Eigen::VectorXd& value,
                                             const StreamOptions& stream, double g0) {
  const detail::MappedFile file(path);
  const std::string_view text = file.text();
  const detail::SampleColumns cols = detail::bind_columns(model, text, path, g0);
  const size_t bytes = std::max<size_t>(stream.block_bytes, 1);
  ResidualMax total(model, base, value);
  const int w = cols.wrench_value(), g = cols.gravity_value();
  ordered_blocks<ResidualMax>(
      detail::num_blocks(text, cols, bytes), thread_count(stream),
      [&](size_t k) {
        const auto [begin, end] = detail::block_range(text, cols, bytes, k);
        ResidualMax part(model, base, value);
        detail::parse_block(text, cols, begin, end,
                            [&](const double* v, size_t) { part.add(v, v + g, v + w); });
        file.release(begin, end);
        return part;
      },
      [&](ResidualMax&& part) { total.merge(part); });
  return total.max();
}

IdentifySummary identify_csv(const Model& model, const BaseParameters& base,
                             const std::string& path, const IdentifyOptions& options,
                             const StreamOptions& stream) {
  const IdentifyAccumulator acc = accumulate_csv(model, base, path, stream);
  IdentifySummary out = acc.finish(options);
  if (stream.residual_max)
    out.residual_max = residual_max_csv(model, base, path, out.value, stream);
  return out;
}

}  // namespace massid

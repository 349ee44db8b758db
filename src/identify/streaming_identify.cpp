// Streaming identification (streaming.hpp): per-axis triangular factors folded
// chunk by chunk, merged in a fixed order, solved like identify() does; motion
// rows from a direct sensor-frame kernel (motion_rows.hpp). Motion logs from
// CSV: motion_csv_identify.cpp.
#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "identify/axis_least_squares.hpp"
#include "identify/motion_rows.hpp"
#include "identify/ordered_blocks.hpp"
#include "identify/stream_regressor.hpp"
#include "io/csv_stream.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/parameters.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

using detail::ordered_blocks;
using detail::thread_count;
namespace detail {

// --------------------------------------------------------------- accumulator

struct AccumulatorState {
  const Model* model;
  const BaseParameters* base;
  std::optional<StreamRegressor> reg;  // static: the moment rows, a chunk at a time
  AxisFactors axes;                    // (B: the rows in waiting)
  int pending = 0;
  long long count = 0;
  // The pending rows' samples, a column of kChunk per value: q (joint j at
  // j * kChunk), g, w. Their regressor rows are computed a chunk at a time.
  std::vector<double> qbuf, gbuf, wbuf;
  // Motion (base->motion()): each sample's rows are computed when it is added
  // (MotionRows) and written straight into the axes' B; the pending samples
  // are kept whole (store_sample) for the residual tracking.
  bool motion = false;
  std::optional<MotionRows> mrows;
  std::vector<double> yrow;             // [6 num_mass + 1]: the sample's rows, then 1 (offsets)
  std::array<std::vector<int>, 6> src;  // per axis and column: its value in yrow
  int sample_size = 0;                  // 3 num_joints + 3 + 9 + 6
  std::vector<double> pending_samples;  // [kChunk x sample_size]
  // The first `keep` samples (store_sample) and the joint ranges, for the
  // identifiability diagnosis (check_identifiability re-tests the data's
  // first max(3p, 30) samples with perturbed poses, and names joints that
  // never move).
  int keep = 0;
  std::vector<double> kept;  // [kept samples x sample_size]
  std::vector<double> qmin, qmax;
  std::string source = "<samples>";
  // Filtered rows: their noise correlation (set_noise_lags) and the
  // lagged products of the covariance's sandwich (axis_least_squares.hpp).
  LagProducts lags;
  LagProducts::Rows lag_rows;
  bool gravity_from_force = false;
  bool gravity_from_upstream = false;  // gravity from the joints above the sensor link

  // Largest residual without a second pass (see track_residuals): with a
  // provisional estimate xhat, each axis keeps the kCandidates rows of largest
  // |y - a xhat| (the sample: q, g, w; in motion q, qd, qdd, g, sensor
  // motion, w), `dropped` bounds |y - a xhat| of every other row, and `anorm2`
  // is the largest |a|^2 of the axis' regressor rows. Once x is known, a
  // dropped row's residual is at most dropped + |a| |x - xhat|.
  static constexpr int kCandidates = 64;
  struct Candidate {
    double value;
    std::vector<double> row;  // the sample (above)
    double lev = 0.0;         // its leverage in the pilot's metric (below)
  };
  int max_candidates = kCandidates;
  // Leverage bound (track_residuals with the pilot accumulator): R_p, the
  // pilot's triangular factor over all unknowns (its six axes stacked); a
  // row a of axis a changes its residual between xhat and x by at most
  // |a R_p^-1| |R_p (x - xhat)| (a over all unknowns): `dropped_lev` is the
  // largest squared leverage |a R_p^-1|^2 over the axis' dropped rows. With
  // M_a the rows of R_p^-1 of the axis' unknowns, |a M_a|^2 = |a L_a|^2 for
  // the Cholesky factor L_a of M_a M_a^T (the axis' columns only: cheaper).
  // Rows are admitted as candidates from 2 sigma of the pilot's residuals on.
  struct Leverage {
    Eigen::MatrixXd R;                 // R_p
    std::array<Eigen::MatrixXd, 6> L;  // per axis
    std::array<bool, 6> ok{};          // false: no bound for the axis
    std::array<double, 6> admit{};     // 2 sigma
  };
  std::shared_ptr<const Leverage> leverage;  // shared by the accumulators of a stream
  std::array<double, 6> dropped_lev{};
  Eigen::MatrixXd zbuf;  // [kChunk x p] scratch
  bool track = false;
  Eigen::VectorXd xhat;
  std::array<std::vector<Candidate>, 6> candidates;
  std::array<double, 6> dropped{}, anorm2{}, admit{};
  std::array<std::vector<double>, 6> amax;  // per axis and column: the largest |a_c|
  std::vector<double> pred, norm2;          // [kChunk] scratch of predict
  // ResidualMax: the rows are not folded, only their largest residual at
  // xhat per axis is kept (residual_rows; in motion add() finds it row by
  // row, sparing the scatter into B).
  bool residual_only = false;
  Vector6d largest = Vector6d::Zero();

  AccumulatorState(const Model& m, const BaseParameters& b)
      : model(&m), base(&b), motion(b.motion()) {
    const int off = b.offset ? 1 : 0;
    const int nj = m.num_joints();
    sample_size = 3 * nj + 3 + 9 + 6;
    if (motion) {
      mrows.emplace(m, b);
      const int nm = b.num_mass(), P = b.layout.per_link();
      yrow.assign(6 * static_cast<size_t>(nm) + 1, 0.0);
      yrow.back() = 1.0;
      pending_samples.resize(static_cast<size_t>(kChunk) * sample_size);
      for (int a = 0; a < 6; ++a) {
        AxisFactor& ax = axes[a];
        for (int i = 0; i < nm; ++i)
          if (a < 3 ? b.column[i] % P < kIxx : b.column[i] != kMass) ax.unknown.push_back(i);
        if (off) ax.unknown.push_back(nm + a);
        for (int u : ax.unknown) src[a].push_back(u < nm ? 6 * u + a : 6 * nm);
      }
    } else {
      reg.emplace(m, b, kChunk);
      qbuf.resize(static_cast<size_t>(nj) * kChunk);
      gbuf.resize(3 * kChunk);
      wbuf.resize(6 * kChunk);
      for (int a = 0; a < 6; ++a) {
        AxisFactor& ax = axes[a];
        if (a < 3) {
          ax.unknown.push_back(b.total_mass);
        } else {
          ax.unknown = reg->unknown();
        }
        if (off) ax.unknown.push_back(b.num_mass() + a);
      }
    }
    for (AxisFactor& ax : axes)
      static_cast<FoldedRows&>(ax) = FoldedRows(static_cast<int>(ax.unknown.size()) + 1, kChunk);
    keep = 8 * b.num_unknowns() + 64;
    admit.fill(-1.0);
    dropped.fill(-1.0);  // -1: no row dropped
    qmin.assign(nj, std::numeric_limits<double>::infinity());
    qmax.assign(nj, -std::numeric_limits<double>::infinity());
  }

  // Folds the pending rows: their regressor rows (force axes: g, 1, w; moment
  // axes: the moment rows, 1, w) into the axes' B, then B into R. (In motion
  // the rows are in B already.)
  void flush() {
    if (pending == 0) return;
    const int m = pending;
    if (!motion) {
      const int K = reg->size();
      const bool off = base->offset;
      for (int a = 0; a < 6; ++a) {
        AxisFactor& ax = axes[a];
        double* B = ax.B.data();
        const double* src_g = a < 3 ? gbuf.data() + a * kChunk : nullptr;
        const int first = a < 3 ? 1 : K;  // columns before the offset's
        for (int r = 0; r < m; ++r) {
          if (src_g) B[r] = src_g[r];
          if (off) B[first * kChunk + r] = 1.0;
          B[(ax.n() - 1) * kChunk + r] = wbuf[a * kChunk + r];
        }
      }
      double* const out[3] = {axes[3].B.data(), axes[4].B.data(), axes[5].B.data()};
      reg->compute(m, qbuf.data(), gbuf.data(), kChunk, out, kChunk);
    }
    if (residual_only) {
      residual_rows(m);
    } else {
      if (track) track_rows(m);
      for (AxisFactor& ax : axes) ax.fold(m);
    }
    pending = 0;
  }

  // The sample as kept: q, qd, qdd, g, sensor motion, w (zeros for null parts).
  void store_sample(const MotionRow& s, double* out) const {
    const int nj = model->num_joints();
    const auto put = [&](const double* v, int n) {
      if (v)
        std::copy_n(v, n, out);
      else
        std::fill_n(out, n, 0.0);
      out += n;
    };
    put(s.q, nj);
    put(s.qd, nj);
    put(s.qdd, nj);
    put(s.gravity, 3);
    put(s.sensor_motion, 9);
    put(s.wrench, 6);
  }

  void add(const MotionRow& s) {
    const int r = pending;
    const int nj = model->num_joints();
    if (motion) {
      mrows->compute(s.q, s.qd, s.qdd, s.gravity, s.sensor_motion, yrow.data());
      const double* y = yrow.data();
      if (residual_only) {  // ResidualMax: the residuals now (as predict, one row)
        for (int a = 0; a < 6; ++a) {
          double p = 0.0;
          for (size_t c = 0; c < src[a].size(); ++c) p += y[src[a][c]] * xhat[axes[a].unknown[c]];
          largest[a] = std::max(largest[a], std::abs(s.wrench[a] - p));
        }
        return;
      }
      for (int a = 0; a < 6; ++a) {
        AxisFactor& ax = axes[a];
        double* B = ax.B.data() + r;
        const int* from = src[a].data();
        const int nc = ax.n() - 1;
        for (int c = 0; c < nc; ++c) B[static_cast<size_t>(c) * kChunk] = y[from[c]];
        B[static_cast<size_t>(nc) * kChunk] = s.wrench[a];
      }
      if (track) store_sample(s, pending_samples.data() + static_cast<size_t>(r) * sample_size);
      if (lags.active()) {
        lag_rows.setZero();
        for (int a = 0; a < 6; ++a)
          for (size_t c = 0; c < src[a].size(); ++c) lag_rows(axes[a].unknown[c], a) = y[src[a][c]];
        lag_rows.bottomRows<1>() = Eigen::Map<const Eigen::Matrix<double, 1, 6>>(s.wrench);
        lags.add(lag_rows, s.run);
      }
    } else {
      for (int j = 0; j < nj; ++j) qbuf[j * kChunk + r] = s.q[j];
      for (int k = 0; k < 3; ++k) gbuf[k * kChunk + r] = s.gravity[k];
      for (int k = 0; k < 6; ++k) wbuf[k * kChunk + r] = s.wrench[k];
    }
    if (++pending == kChunk) flush();
    if (count < keep) {
      kept.resize(kept.size() + sample_size);
      store_sample(s, kept.data() + kept.size() - sample_size);
    }
    for (int j = 0; j < nj; ++j) {
      qmin[j] = std::min(qmin[j], s.q[j]);
      qmax[j] = std::max(qmax[j], s.q[j]);
    }
    ++count;
  }

  void track_residuals(const Eigen::VectorXd& estimate) {
    track = true;
    xhat = estimate;
  }

  // The leverage bound from the pilot (same base): the QR of its six axes'
  // factors stacked. A pilot that does not determine every unknown gives no
  // bound (infinite leverage).
  void track_leverage(const AccumulatorState& pilot) {
    AccumulatorState st = pilot;
    st.flush();
    auto lev = std::make_shared<Leverage>();
    const int p = base->num_unknowns();
    // Each axis weighted by its noise as the pilot sees it (|R_a [xhat; -1]|^2
    // is its residual sum of squares), so that the metric suits every axis.
    Vector6d sigmas;
    const double dof = std::max(1.0, static_cast<double>(st.count) - p / 6.0);
    for (int a = 0; a < 6; ++a) {
      const AxisFactor& ax = st.axes[a];
      const double ssr = axis_ssr(ax, xhat);
      const double signal = ax.R.col(ax.n() - 1).norm();
      const double sigma = std::max(std::sqrt(ssr / dof), 1e-13 * signal + 1e-300);
      lev->admit[a] = 2.0 * sigma;
      sigmas[a] = sigma;
    }
    lev->R = qr_factor(stacked_factors(st.axes, p, false, sigmas));
    const Eigen::VectorXd d = lev->R.diagonal().cwiseAbs();
    const bool regular = p > 0 && d.minCoeff() > 1e-13 * d.maxCoeff();
    const Eigen::MatrixXd inv =
        regular ? Eigen::MatrixXd(
                      lev->R.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(p, p)))
                : Eigen::MatrixXd::Zero(p, p);
    for (int a = 0; a < 6; ++a) {
      const AxisFactor& ax = axes[a];
      Eigen::MatrixXd M(ax.n() - 1, p);
      for (int c = 0; c < ax.n() - 1; ++c) M.row(c) = inv.row(ax.unknown[c]);
      const Eigen::LLT<Eigen::MatrixXd> llt(M * M.transpose());
      lev->ok[a] = regular && llt.info() == Eigen::Success;
      lev->L[a] = lev->ok[a] ? Eigen::MatrixXd(llt.matrixL())
                             : Eigen::MatrixXd::Zero(ax.n() - 1, ax.n() - 1);
    }
    use_leverage(std::move(lev));
  }

  void use_leverage(std::shared_ptr<const Leverage> lev) {
    leverage = std::move(lev);
    max_candidates = 1024;
    for (int a = 0; a < 6; ++a) {
      dropped_lev[a] = leverage->ok[a] ? 0.0 : std::numeric_limits<double>::infinity();
      admit[a] = leverage->ok[a] ? leverage->admit[a] : -1.0;
    }
  }

  // Keeps the kCandidates largest, ties in row order (stable); the others
  // raise `dropped`.
  void prune(int a) {
    auto& c = candidates[a];
    const int K = max_candidates;
    std::stable_sort(c.begin(), c.end(),
                     [](const Candidate& x, const Candidate& y) { return x.value > y.value; });
    if (static_cast<int>(c.size()) > K) {
      dropped[a] = std::max(dropped[a], c[K].value);
      for (size_t i = K; i < c.size(); ++i) dropped_lev[a] = std::max(dropped_lev[a], c[i].lev);
      c.resize(K);
    }
    admit[a] = std::max(admit[a], static_cast<int>(c.size()) == K ? c.back().value : -1.0);
  }

  // pred = A_a xhat (and with `norms`, norm2 = |row of A_a|^2) of the m
  // pending rows of axis a (in B, before folding), column by column (over
  // rows r).
  void predict(const AxisFactor& ax, int m, bool norms) {
    pred.resize(kChunk);
    norm2.resize(kChunk);
    const double* x = xhat.data();
    for (int r = 0; r < m; ++r) pred[r] = norm2[r] = 0.0;
    for (int c = 0; c + 1 < ax.n(); ++c) {
      const double* col = ax.B.data() + c * kChunk;
      const double xc = x[ax.unknown[c]];
      for (int r = 0; r < m; ++r) pred[r] += col[r] * xc;
      if (norms)
        for (int r = 0; r < m; ++r) norm2[r] += col[r] * col[r];
    }
  }

  // ResidualMax: the largest |y - A_a xhat| per axis, over the m pending rows.
  void residual_rows(int m) {
    for (int a = 0; a < 6; ++a) {
      predict(axes[a], m, false);
      const double* y = axes[a].B.data() + (axes[a].n() - 1) * kChunk;
      for (int r = 0; r < m; ++r) largest[a] = std::max(largest[a], std::abs(y[r] - pred[r]));
    }
  }

  // The residuals at xhat of the m pending rows, whose regressor rows are in
  // the axes' B (before folding), in row order.
  void track_rows(int m) {
    const int nj = model->num_joints();
    for (int a = 0; a < 6; ++a) {
      const AxisFactor& ax = axes[a];
      predict(ax, m, true);
      if (motion && !leverage) {  // per column too (the static rows are proven without)
        std::vector<double>& big = amax[a];
        big.resize(ax.n() - 1, 0.0);
        for (int c = 0; c + 1 < ax.n(); ++c) {
          const double* col = ax.B.data() + c * kChunk;
          double largest = big[c];
          for (int r = 0; r < m; ++r) largest = std::max(largest, std::abs(col[r]));
          big[c] = largest;
        }
      }
      if (leverage) {  // |a R_p^-1|^2 of each row
        const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> A(
            ax.B.data(), m, ax.n() - 1, Eigen::OuterStride<>(kChunk));
        zbuf.resize(kChunk, ax.n() - 1);
        zbuf.topRows(m).noalias() = A * leverage->L[a].triangularView<Eigen::Lower>();
      }
      const double* y = ax.B.data() + (ax.n() - 1) * kChunk;
      for (int r = 0; r < m; ++r) {
        anorm2[a] = std::max(anorm2[a], norm2[r]);
        const double value = std::abs(y[r] - pred[r]);
        const double lev = leverage ? zbuf.row(r).squaredNorm() : 0.0;
        if (value <= admit[a]) {
          dropped[a] = std::max(dropped[a], value);
          dropped_lev[a] = std::max(dropped_lev[a], lev);
          continue;
        }
        Candidate c{value, {}, lev};
        if (motion) {
          const double* sample = pending_samples.data() + static_cast<size_t>(r) * sample_size;
          c.row.assign(sample, sample + sample_size);
        } else {  // (as store_sample lays it out)
          c.row.assign(sample_size, 0.0);
          for (int j = 0; j < nj; ++j) c.row[j] = qbuf[j * kChunk + r];
          for (int k = 0; k < 3; ++k) c.row[3 * nj + k] = gbuf[k * kChunk + r];
          for (int k = 0; k < 6; ++k) c.row[3 * nj + 12 + k] = wbuf[k * kChunk + r];
        }
        candidates[a].push_back(std::move(c));
        if (static_cast<int>(candidates[a].size()) >= 2 * max_candidates) prune(a);
      }
    }
  }

  // Appends `later`'s rows (both are flushed first).
  void merge(AccumulatorState& later) {
    later.flush();
    flush();
    if (later.count == 0) return;
    for (int a = 0; a < 6; ++a) {
      if (count == 0)
        axes[a].R = later.axes[a].R;
      else
        axes[a].merge(later.axes[a]);
    }
    const size_t room =
        std::max(static_cast<size_t>(keep) * sample_size, kept.size()) - kept.size();
    kept.insert(
        kept.end(), later.kept.begin(),
        later.kept.begin() + static_cast<std::ptrdiff_t>(std::min(later.kept.size(), room)));
    count += later.count;
    lags.merge(later.lags);
    if (track) {
      for (int a = 0; a < 6; ++a) {
        for (auto& c : later.candidates[a]) candidates[a].push_back(std::move(c));
        dropped[a] = std::max(dropped[a], later.dropped[a]);
        dropped_lev[a] = std::max(dropped_lev[a], later.dropped_lev[a]);
        anorm2[a] = std::max(anorm2[a], later.anorm2[a]);
        if (amax[a].size() < later.amax[a].size()) amax[a].resize(later.amax[a].size(), 0.0);
        for (size_t c = 0; c < later.amax[a].size(); ++c)
          amax[a][c] = std::max(amax[a][c], later.amax[a][c]);
        prune(a);
      }
    }
    for (size_t j = 0; j < qmin.size(); ++j) {
      qmin[j] = std::min(qmin[j], later.qmin[j]);
      qmax[j] = std::max(qmax[j], later.qmax[j]);
    }
  }
};

}  // namespace detail

namespace {

using detail::AccumulatorState;

using Vector6d = Eigen::Matrix<double, 6, 1>;

// The rows of identification come from a source cut into fixed blocks:
// block(k, sink) calls sink(MotionRow) for block k's rows in order. The passes
// below (accumulate_rows, residual_max_rows) are the one code over every source:
// Samples in memory (SamplesRows) and a data CSV file (CsvRows).

// Samples in memory, `rows` a block (sample i copied into a buffer: q, qd, qdd,
// g, sensor motion, w; with a static base only q, g, w).
struct SamplesRows {
  const Samples& samples;
  size_t rows = 1;
  int nj = 0;
  bool velocities = false, sensor = false;

  SamplesRows(const Samples& s, bool motion, size_t block_rows)
      : samples(s),
        rows(std::max<size_t>(block_rows, 1)),
        nj(static_cast<int>(s.q.cols())),
        velocities(motion && s.qd.cols() == nj && s.qdd.cols() == nj),
        sensor(motion && s.has_sensor_motion()) {
    if (!s.has_wrench())
      throw InputError(s.source + ": no measured wrench (columns fx,fy,fz,mx,my,mz)");
  }
  size_t size() const { return static_cast<size_t>(samples.size()); }
  size_t blocks() const { return (size() + rows - 1) / rows; }
  void set_source(IdentifyAccumulator& acc) const {
    acc.set_source(samples.source, samples.gravity_from_force, samples.gravity_from_upstream);
    acc.set_noise_lags(samples.noise_lags);
  }
  template <class Sink>
  void range(size_t begin, size_t end, Sink&& sink) const {
    std::vector<double> b(3 * static_cast<size_t>(nj) + 18);
    double* const v = b.data();
    double* const g = v + 3 * nj;
    const MotionRow row{v, velocities ? v + nj : nullptr, velocities ? v + 2 * nj : nullptr,
                        g, sensor ? g + 3 : nullptr,      g + 12};
    for (size_t i = begin; i < end; ++i) {
      const Eigen::Index r = static_cast<Eigen::Index>(i);
      for (int j = 0; j < nj; ++j) v[j] = samples.q(r, j);
      if (velocities)
        for (int j = 0; j < nj; ++j) {
          v[nj + j] = samples.qd(r, j);
          v[2 * nj + j] = samples.qdd(r, j);
        }
      for (int k = 0; k < 3; ++k) g[k] = samples.gravity(r, k);
      if (sensor)
        for (int k = 0; k < 9; ++k) g[3 + k] = samples.sensor_motion(r, k);
      for (int k = 0; k < 6; ++k) g[12 + k] = samples.wrench(r, k);
      MotionRow at = row;
      at.run = i < samples.block.size() ? samples.block[i] : 0.0;
      sink(at);
    }
  }
  template <class Sink>
  void block(size_t k, Sink&& sink) const {
    range(k * rows, std::min(size(), (k + 1) * rows), sink);
  }
};

// A data CSV file, memory-mapped, `bytes` a block (cut at line starts), the
// pages of a block released once parsed. Gravity as read_samples takes it:
// read, from the force (parse_block), or from the joints above the sensor
// link (upstream_sensor_frame, the root gravity bound with the columns).
struct CsvRows {
  const Model& model;
  detail::MappedFile file;
  std::string_view text;
  detail::SampleColumns cols;
  size_t bytes = 1;

  CsvRows(const Model& m, const std::string& path, const SampleOptions& read,
          const StreamOptions& stream)
      : model(m),
        file(path),
        text(file.text()),
        cols(detail::bind_columns(m, text, path, read)),
        bytes(std::max<size_t>(stream.block_bytes, 1)) {}
  size_t blocks() const { return detail::num_blocks(text, cols, bytes); }
  void set_source(IdentifyAccumulator& acc) const {
    acc.set_source(cols.source, cols.gravity_from_force, cols.gravity_from_upstream);
  }
  template <class Sink>
  void range(size_t begin, size_t end, Sink&& sink) const {
    const int w = cols.wrench_value();
    double gb[3];
    detail::parse_block(text, cols, begin, end, [&](const double* v, size_t) {
      const double* g = v + cols.gravity_value();
      if (cols.gravity_from_upstream) {
        upstream_sensor_frame(model, v + cols.q_up, nullptr, nullptr, cols.root_gravity, gb,
                              nullptr);
        g = gb;
      }
      sink(MotionRow{v, nullptr, nullptr, g, nullptr, v + w});
    });
  }
  template <class Sink>
  void block(size_t k, Sink&& sink) const {
    const auto [begin, end] = detail::block_range(text, cols, bytes, k);
    range(begin, end, sink);
    file.release(begin, end);
  }
  // The end of the first `pilot_bytes` (at a line start).
  size_t pilot_end(size_t pilot_bytes) const {
    return detail::block_range(text, cols, std::max<size_t>(pilot_bytes, 1), 0).second;
  }
};

// Every row of `src` added to a partial per block (make(): an empty one, for
// every block and the total), blocks on threads merged in block order.
template <class Partial, class Source, class Make>
Partial reduce_rows(const Source& src, const StreamOptions& stream, Make make) {
  Partial total = make();
  ordered_blocks<Partial>(
      src.blocks(), thread_count(stream),
      [&](size_t k) {
        Partial part = make();
        src.block(k, [&](const MotionRow& r) { part.add(r); });
        return part;
      },
      [&](Partial&& part) { total.merge(std::move(part)); });
  return total;
}

// Every row of `src` folded; with `xhat`, each partial tracking the residuals
// at it (track_residuals).
template <class Source>
IdentifyAccumulator accumulate_rows(const Model& model, const BaseParameters& base,
                                    const Source& src, const StreamOptions& stream,
                                    const std::optional<Eigen::VectorXd>& xhat = std::nullopt) {
  return reduce_rows<IdentifyAccumulator>(src, stream, [&] {
    IdentifyAccumulator acc(model, base);
    src.set_source(acc);  // (the noise lags: the partials pair their rows)
    if (xhat) acc.track_residuals(*xhat);
    return acc;
  });
}

// The largest residual per axis of `value` over every row of `src`.
template <class Source>
Vector6d residual_max_rows(const Model& model, const BaseParameters& base, const Source& src,
                           const Eigen::VectorXd& value, const StreamOptions& stream) {
  return reduce_rows<ResidualMax>(src, stream, [&] { return ResidualMax(model, base, value); })
      .max();
}

}  // namespace

// --------------------------------------------------------------- IdentifyAccumulator

IdentifyAccumulator::IdentifyAccumulator(const Model& model, const BaseParameters& base)
    : state_(std::make_unique<AccumulatorState>(model, base)) {}
IdentifyAccumulator::~IdentifyAccumulator() = default;
IdentifyAccumulator::IdentifyAccumulator(IdentifyAccumulator&&) noexcept = default;
IdentifyAccumulator& IdentifyAccumulator::operator=(IdentifyAccumulator&&) noexcept = default;

void IdentifyAccumulator::add(const MotionRow& row) { state_->add(row); }

void IdentifyAccumulator::add(const Samples& samples) {
  if (state_->count == 0 && samples.noise_lags > 0) set_noise_lags(samples.noise_lags);
  const SamplesRows rows(samples, state_->motion, 1);
  rows.range(0, rows.size(), [&](const MotionRow& r) { state_->add(r); });
}

void IdentifyAccumulator::merge(IdentifyAccumulator&& later) { state_->merge(*later.state_); }

void IdentifyAccumulator::set_noise_lags(int lags) {
  if (state_->count > 0) throw std::logic_error("IdentifyAccumulator::set_noise_lags: after add()");
  if (lags <= 0 || !state_->motion) {
    state_->lags = detail::LagProducts();
    return;
  }
  const int p = state_->base->num_unknowns();
  state_->lags = detail::LagProducts(lags, p);
  state_->lag_rows = detail::LagProducts::Rows::Zero(p + 1, 6);
}

void IdentifyAccumulator::track_residuals(const Eigen::VectorXd& estimate,
                                          const IdentifyAccumulator* pilot) {
  state_->track_residuals(estimate);
  if (pilot) state_->track_leverage(*pilot->state_);
}

IdentifyAccumulator IdentifyAccumulator::empty_like() const {
  IdentifyAccumulator out(*state_->model, *state_->base);
  out.set_source(state_->source, state_->gravity_from_force, state_->gravity_from_upstream);
  if (state_->lags.active()) {
    out.state_->lags = state_->lags.empty_like();
    out.state_->lag_rows = state_->lag_rows;
  }
  if (state_->track) out.state_->track_residuals(state_->xhat);
  if (state_->leverage) out.state_->use_leverage(state_->leverage);
  return out;
}

Eigen::VectorXd IdentifyAccumulator::rough_estimate() const {
  AccumulatorState st = *state_;  // the pending rows folded in (a copy: this is const)
  st.flush();
  const int p = st.base->num_unknowns();
  const Eigen::MatrixXd Ay = detail::stacked_factors(st.axes, p, true);  // [A y]
  const auto A = Ay.leftCols(p);
  const Eigen::VectorXd y = Ay.col(p);
  const Eigen::VectorXd scale = detail::column_scale(A);
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A * scale.asDiagonal());
  return scale.asDiagonal() * cod.solve(y);
}

void IdentifyAccumulator::set_source(const std::string& source, bool gravity_from_force,
                                     bool gravity_from_upstream) {
  state_->source = source;
  state_->gravity_from_force = gravity_from_force;
  state_->gravity_from_upstream = gravity_from_upstream;
}

IdentifySummary IdentifyAccumulator::finish(const IdentifyOptions& options) const {
  // The pending rows folded in (and tracked), on a copy: finish is const.
  AccumulatorState flushed = *state_;
  flushed.flush();
  const AccumulatorState& st = flushed;
  const BaseParameters& base = *st.base;
  const Model& model = *st.model;
  const long long N = st.count;
  const int p = base.num_unknowns();

  detail::check_unknowns(st.source, base, st.gravity_from_force, N);
  const detail::AxisFactors& factors = st.axes;

  // Identifiability on the factors, which have the singular values (and
  // right singular vectors) of the stacked regressor. The perturbed-pose hints need samples:
  // the first `keep` ones (check_identifiability uses the first max(3p, 30)),
  // and, when there are more, two rows holding each joint's minimum and
  // maximum so that "JOINT never moves" is judged on all the data.
  {
    const int nj = model.num_joints();
    const int kept = static_cast<int>(st.kept.size()) / st.sample_size;
    const int extra = N > kept ? 2 : 0;
    // The kept samples as store_sample laid them out, one a row, then the two
    // range rows (gravity as the first sample's, no motion).
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor K = RowMajor::Zero(kept + extra, st.sample_size);
    K.topRows(kept) = Eigen::Map<const RowMajor>(st.kept.data(), kept, st.sample_size);
    for (int e = 0; e < extra; ++e) {
      K.row(kept + e).head(nj) =
          Eigen::Map<const Eigen::RowVectorXd>((e == 0 ? st.qmin : st.qmax).data(), nj);
      K.row(kept + e).segment(3 * nj, 3) = K.row(0).segment(3 * nj, 3);
    }
    Samples sub;
    sub.source = st.source;
    sub.gravity_from_force = st.gravity_from_force;
    sub.q = K.leftCols(nj);
    sub.gravity = K.middleCols(3 * nj, 3);
    if (st.motion) {
      sub.qd = K.middleCols(nj, nj);
      sub.qdd = K.middleCols(2 * nj, nj);
      sub.sensor_motion = K.middleCols(3 * nj + 3, 9);
    }
    detail::check_identifiable(model, base, sub, N, factors, options.rank_tolerance);
  }

  IdentifySummary out =
      detail::start_summary(N, st.gravity_from_force, st.gravity_from_upstream, options);
  detail::NoiseFit fit = detail::fit_noise(factors, p, static_cast<double>(N), options);
  fit.solution.covariance = st.lags.covariance(fit.solution.covariance, fit.sigma, fit.solution.x,
                                               fit.solution.ssr, static_cast<double>(N));
  detail::fill_summary(out, fit, p, static_cast<double>(N));
  const Eigen::VectorXd& x = out.value;
  out.residual_max.setConstant(std::numeric_limits<double>::quiet_NaN());
  if (st.track) {
    // The exact residuals of the candidate rows (as residual_max_csv computes
    // them); the maximum is proven when no dropped row can exceed it.
    ResidualMax exact(model, base, x);
    const int nj = model.num_joints();
    for (const auto& axis : st.candidates)
      for (const auto& c : axis) {
        const double* v = c.row.data();  // (store_sample's layout)
        exact.add(MotionRow{v, v + nj, v + 2 * nj, v + 3 * nj, v + 3 * nj + 3, v + 3 * nj + 12});
      }
    const Vector6d M = exact.max();
    bool proven = true;
    for (int a = 0; a < 6; ++a) {
      if (st.dropped[a] < 0) continue;  // every row is a candidate
      // |a (x - xhat)| <= |a| |x - xhat|, and (motion) <= sum_c max|a_c| |x_c - xhat_c|.
      const std::vector<int>& unknown = st.axes[a].unknown;
      double d2 = 0.0, by_column = 0.0;
      for (size_t c = 0; c < unknown.size(); ++c) {
        const double d = x[unknown[c]] - st.xhat[unknown[c]];
        d2 += d * d;
        if (c < st.amax[a].size()) by_column += st.amax[a][c] * std::abs(d);
      }
      double bound = std::sqrt(st.anorm2[a] * d2);
      if (st.motion && !st.amax[a].empty()) bound = std::min(bound, by_column);
      if (st.leverage && std::isfinite(st.dropped_lev[a])) {
        const double moved = (st.leverage->R.triangularView<Eigen::Upper>() * (x - st.xhat)).norm();
        bound = std::min(bound, std::sqrt(st.dropped_lev[a]) * moved);
      }
      proven = proven && st.dropped[a] + 1.001 * bound + 1e-9 * M[a] < M[a];
    }
    if (proven) out.residual_max = M;
  }
  out.condition_number = detail::condition_number(base, factors);
  return out;
}

// --------------------------------------------------------------- ResidualMax

// The accumulator's rows, not folded: their residuals at `value`.
ResidualMax::ResidualMax(const Model& model, const BaseParameters& base,
                         const Eigen::VectorXd& value)
    : state_(std::make_unique<AccumulatorState>(model, base)) {
  state_->residual_only = true;
  state_->keep = 0;
  state_->xhat = value;
}
ResidualMax::~ResidualMax() = default;
ResidualMax::ResidualMax(ResidualMax&&) noexcept = default;

void ResidualMax::add(const double* q, const double* gravity, const double* wrench) {
  state_->add(MotionRow{q, nullptr, nullptr, gravity, nullptr, wrench});
}

void ResidualMax::add(const MotionRow& row) { state_->add(row); }

void ResidualMax::merge(const ResidualMax& other) {
  other.state_->flush();
  state_->flush();
  state_->largest = state_->largest.cwiseMax(other.state_->largest);
}

// (Evaluates the samples still buffered: logically const.)
Eigen::Matrix<double, 6, 1> ResidualMax::max() const {
  state_->flush();
  return state_->largest;
}

// --------------------------------------------------------------- drivers

IdentifySummary identify_streaming(const Model& model, const BaseParameters& base,
                                   const Samples& samples, const IdentifyOptions& options,
                                   const StreamOptions& stream) {
  const SamplesRows rows(samples, base.motion(), static_cast<size_t>(stream.block_rows));
  IdentifySummary out = accumulate_rows(model, base, rows, stream).finish(options);
  if (stream.residual_max)
    out.residual_max = residual_max_rows(model, base, rows, out.value, stream);
  return out;
}

IdentifyAccumulator accumulate_csv(const Model& model, const BaseParameters& base,
                                   const std::string& path, const StreamOptions& stream,
                                   const SampleOptions& read) {
  const CsvRows rows(model, path, read, stream);
  // The largest residual in the same pass: a provisional estimate from the
  // rows of the first 2 MB (a pilot, read twice) selects candidate rows, and
  // finish() proves the maximum from them (else it stays NaN and a second pass
  // is needed). Files within the pilot are cheap to read twice anyway.
  std::optional<Eigen::VectorXd> xhat;
  const size_t pilot_end = rows.pilot_end(stream.pilot_bytes);
  if (stream.residual_max && pilot_end < rows.text.size()) {
    IdentifyAccumulator pilot(model, base);
    rows.range(rows.cols.data_begin, pilot_end, [&](const MotionRow& r) { pilot.add(r); });
    xhat = pilot.rough_estimate();
  }
  return accumulate_rows(model, base, rows, stream, xhat);
}

Eigen::Matrix<double, 6, 1> residual_max_csv(const Model& model, const BaseParameters& base,
                                             const std::string& path, const Eigen::VectorXd& value,
                                             const StreamOptions& stream,
                                             const SampleOptions& read) {
  return residual_max_rows(model, base, CsvRows(model, path, read, stream), value, stream);
}

IdentifySummary identify_csv(const Model& model, const BaseParameters& base,
                             const std::string& path, const IdentifyOptions& options,
                             const StreamOptions& stream) {
  IdentifySummary out = accumulate_csv(model, base, path, stream).finish(options);
  if (stream.residual_max)
    out.residual_max = residual_max_csv(model, base, path, out.value, stream);
  return out;
}

}  // namespace massid

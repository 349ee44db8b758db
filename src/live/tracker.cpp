#include "massid/live/tracker.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/simd_clones.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"

namespace massid {

namespace {

using Vector16 = Eigen::Matrix<double, 16, 1>;
using Matrix16 = Eigen::Matrix<double, 16, 16>;
using Matrix6x10 = Eigen::Matrix<double, 6, 10>;
using Matrix10 = Eigen::Matrix<double, 10, 10>;
using Vector10 = Eigen::Matrix<double, 10, 1>;

constexpr int kPayload = 10;  // m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz
constexpr int kOffset = 10;   // the offsets' first index in the state
constexpr int kState = 16;
// LINK's regressor's force rows are zero in the inertia columns (always), its
// moment rows too at rest (omega = omega_dot = 0): the first kRestColumns
// columns (m, h) are all there is then.
constexpr int kRestColumns = 4;

// The rows kept: LINK's regressor and the measured wrench less the
// mechanism's prediction, flagged when beyond the gate.
struct TrackerRow {
  Matrix6x10 Y = Matrix6x10::Zero();
  Wrench z = Wrench::Zero();
  bool moving = false;  // Y's inertia columns are not all zero
  bool flagged = false;
  // A flagged row's share of a refit's normal equations, against the state
  // when it was flagged (a run of flagged rows commits nothing, so the state
  // stays that): A = Y^T W Y (its first kRestColumns rows and columns only
  // when !moving), b = Y^T W e, ee = e^T W e, e = z - H x, W = R^-1.
  Matrix10 A = Matrix10::Zero();
  Vector10 b = Vector10::Zero();
  double ee = 0.0;
};

// A column of the state's 16 values in four V4 (simd_clones.hpp), named so
// that they stay in registers.
struct TrackerColumn {
  detail::V4 a, b, c, d;
};
[[gnu::always_inline]] inline void tracker_load(TrackerColumn& v, const double* p) {
  detail::load4(v.a, p);
  detail::load4(v.b, p + 4);
  detail::load4(v.c, p + 8);
  detail::load4(v.d, p + 12);
}
[[gnu::always_inline]] inline void tracker_store(double* p, const TrackerColumn& v) {
  detail::store4(p, v.a);
  detail::store4(p + 4, v.b);
  detail::store4(p + 8, v.c);
  detail::store4(p + 12, v.d);
}
// v += s u (u a column in memory; v -= s u as s -> -s: the same bits).
[[gnu::always_inline]] inline void tracker_add(TrackerColumn& v, double s, const double* u) {
  TrackerColumn w;
  tracker_load(w, u);
  v.a += w.a * s;
  v.b += w.b * s;
  v.c += w.c * s;
  v.d += w.d * s;
}

// A vector of 6 (a wrench, a column of Y or S) as rows 0-3 and 4-5.
using TrackerQuad = detail::V4;
using TrackerPair = double __attribute__((vector_size(16)));
[[gnu::always_inline]] inline void tracker_load6(TrackerQuad& a, TrackerPair& b, const double* p) {
  detail::load4(a, p);
  std::memcpy(&b, p + 4, sizeof b);
}
[[gnu::always_inline]] inline void tracker_store6(double* p, const TrackerQuad& a,
                                                  const TrackerPair& b) {
  detail::store4(p, a);
  std::memcpy(p + 4, &b, sizeof b);
}

// A symmetric 3 x 3 matrix is positive definite: its leading minors are
// positive (Sylvester).
bool tracker_positive_definite(const Eigen::Matrix3d& A) {
  return A(0, 0) > 0.0 && A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0) > 0.0 && A.determinant() > 0.0;
}

// Column `i` of P H^T for H = [Y | I6]: P's offset column plus Y's row i
// on P's first `Columns` columns (those Y can have non-zero in that row).
template <int Columns>
[[gnu::always_inline]] inline void tracker_pht_column(const double* P, const double* Y, int i,
                                                      double* out) {
  TrackerColumn acc;
  tracker_load(acc, P + kState * (kOffset + i));
#pragma GCC unroll 10
  for (int k = 0; k < Columns; ++k) tracker_add(acc, Y[6 * k + i], P + kState * k);
  tracker_store(out, acc);
}

}  // namespace

// The filter's arithmetic on one row, on raw arrays (column-major, as Eigen
// stores them): x [16], P [16 x 16] symmetric, Y [6 x 10], z [6], R [6] (the
// noise's variances). tracker_innovation() forms the innovation e = z - H x,
// P H^T [16 x 6] (PHt), the factors S = H P H^T + R = L D L^T (L [6 x 6]
// unit lower below its diagonal, D on it, column-major; inv = D^-1) and
// v = L^-1 e, and returns d^2 = e^T S^-1 e = v^T D^-1 v. tracker_correct()
// then turns PHt into G = P H^T L^-T D^-1/2 in place and applies the update
// in its symmetric form: x += G D^-1/2 v (= K e), P -= G G^T
// (= P H^T S^-1 H P), exactly symmetric as P was. An AVX2 copy where the CPU
// has it (same bits).
namespace detail {

// tracker_innovation for Y's first `Columns` columns: 10 in motion, 4 at rest.
template <int Columns>
[[gnu::always_inline]] inline double tracker_innovation_columns(const double* x, const double* P,
                                                                const double* Y, const double* z,
                                                                const double* R, double* PHt,
                                                                double* L, double* inv, double* v) {
  // Y's columns (6 values each) as rows 0-3 and 4-5; the force rows of the
  // inertia columns are zero, so all columns are taken alike.
  TrackerQuad e4, z4;
  TrackerPair e2, z2;
  tracker_load6(e4, e2, z);
  tracker_load6(z4, z2, x + kOffset);
  e4 -= z4;
  e2 -= z2;
#pragma GCC unroll 10
  for (int k = 0; k < Columns; ++k) {
    tracker_load6(z4, z2, Y + 6 * k);
    e4 -= z4 * x[k];
    e2 -= z2 * x[k];
  }
#pragma GCC unroll 16
  for (int i = 0; i < 3; ++i) tracker_pht_column<kRestColumns>(P, Y, i, PHt + kState * i);
#pragma GCC unroll 16
  for (int i = 3; i < 6; ++i) tracker_pht_column<Columns>(P, Y, i, PHt + kState * i);
    // S = H P H^T + R, column by column, into L.
#pragma GCC unroll 16
  for (int j = 0; j < 6; ++j) {
    const double* c = PHt + kState * j;
    TrackerQuad s4;
    TrackerPair s2;
    tracker_load6(s4, s2, c + kOffset);
#pragma GCC unroll 10
    for (int k = 0; k < Columns; ++k) {
      tracker_load6(z4, z2, Y + 6 * k);
      s4 += z4 * c[k];
      s2 += z2 * c[k];
    }
    tracker_store6(L + 6 * j, s4, s2);
    L[6 * j + j] += R[j];
  }
  // S = L D L^T in place: L unit lower (below the diagonal), D on the
  // diagonal, its reciprocals in inv (no square root on the dependent chain).
#pragma GCC unroll 16
  for (int j = 0; j < 6; ++j) {
    double t[6];  // L(j, k) D(k)
    double d = L[6 * j + j];
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) {
      t[k] = L[6 * k + j] * L[6 * k + k];
      d -= L[6 * k + j] * t[k];
    }
    L[6 * j + j] = d;
    inv[j] = 1.0 / d;
#pragma GCC unroll 16
    for (int i = j + 1; i < 6; ++i) {
      double s = L[6 * j + i];
#pragma GCC unroll 16
      for (int k = 0; k < j; ++k) s -= L[6 * k + i] * t[k];
      L[6 * j + i] = s * inv[j];
    }
  }
  // v = L^-1 e, d^2 = v^T D^-1 v
  double ev[6];
  tracker_store6(ev, e4, e2);
  double d2 = 0.0;
#pragma GCC unroll 16
  for (int i = 0; i < 6; ++i) {
    double s = ev[i];
#pragma GCC unroll 16
    for (int k = 0; k < i; ++k) s -= L[6 * k + i] * v[k];
    v[i] = s;
    d2 += s * s * inv[i];
  }
  return d2;
}

MASSID_AVX2_CLONES
double tracker_innovation(const double* x, const double* P, const double* Y, bool moving,
                          const double* z, const double* R, double* PHt, double* L, double* inv,
                          double* v) {
  return moving ? tracker_innovation_columns<kPayload>(x, P, Y, z, R, PHt, L, inv, v)
                : tracker_innovation_columns<kRestColumns>(x, P, Y, z, R, PHt, L, inv, v);
}

MASSID_AVX2_CLONES
void tracker_correct(double* x, double* P, double* G, const double* L, const double* inv,
                     const double* v) {
  // G = P H^T L^-T D^-1/2: the forward substitution along each row, then
  // column j scaled by D(j)^-1/2; w = D^-1/2 v.
#pragma GCC unroll 16
  for (int j = 1; j < 6; ++j) {
    TrackerColumn g;
    tracker_load(g, G + kState * j);
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) tracker_add(g, -L[6 * k + j], G + kState * k);
    tracker_store(G + kState * j, g);
  }
  TrackerColumn a;
  tracker_load(a, x);
#pragma GCC unroll 16
  for (int j = 0; j < 6; ++j) {
    const double r = std::sqrt(inv[j]);
    TrackerColumn g;
    tracker_load(g, G + kState * j);
    g.a *= r;
    g.b *= r;
    g.c *= r;
    g.d *= r;
    tracker_store(G + kState * j, g);
    tracker_add(a, v[j] * r, G + kState * j);  // x += G w
  }
  tracker_store(x, a);
  // P -= G G^T: P(r, c) -= sum_j G(r, j) G(c, j), on and below the
  // diagonal's blocks of four rows, then mirrored (the same products in the
  // same order as (c, r) would take: the same bits).
#pragma GCC unroll 16
  for (int c = 0; c < kState; ++c) {
    for (int q = c / 4; q < 4; ++q) {
      double* p = P + kState * c + 4 * q;
      detail::V4 b;
      detail::load4(b, p);
#pragma GCC unroll 6
      for (int j = 0; j < 6; ++j) {
        detail::V4 g;
        detail::load4(g, G + kState * j + 4 * q);
        b -= g * G[kState * j + c];
      }
      detail::store4(p, b);
    }
  }
  for (int c = 4; c < kState; ++c)
    for (int r = 0; r < c / 4 * 4; ++r) P[kState * c + r] = P[kState * r + c];
}

}  // namespace detail

int farthest_link(const Model& model) {
  int best = 0, best_depth = -1;
  for (int l = 0; l < model.num_links(); ++l) {
    int depth = 0;
    for (int p = l; model.links[static_cast<std::size_t>(p)].parent >= 0;
         p = model.links[static_cast<std::size_t>(p)].parent)
      ++depth;
    if (depth >= best_depth) best = l, best_depth = depth;
  }
  return best;
}

Eigen::Matrix3d consistent_inertia(const Eigen::Matrix3d& I) {
  // The second moments D = tr(I)/2 - I (eigenvalues d before the clamp):
  // positive definite, nothing is clamped and I is its own projection;
  // negative definite, everything is, and it is zero; else the eigen path.
  const Eigen::Matrix3d D = Eigen::Matrix3d::Identity() * (0.5 * I.trace()) - I;
  if (tracker_positive_definite(D)) return I;
  if (tracker_positive_definite(-D)) return Eigen::Matrix3d::Zero();
  // One or two of d (descending, l ascending) clamp: D+ = D - d_2 P_2 or
  // d_0 P_0, the eigenprojections P_k = prod_{j != k} (I - l_j) / (l_k -
  // l_j) (Frobenius; no eigenvectors). The clamped |d| is at most the gap
  // divided by, so the error stays at round-off of |I|.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(I, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d l = eig.eigenvalues();
  const Eigen::Vector3d d = Eigen::Vector3d::Constant(0.5 * l.sum()) - l;
  const Eigen::Matrix3d One = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d Dp;
  if (d[0] <= 0.0) {
    Dp.setZero();
  } else if (d[2] >= 0.0) {
    // Nothing to clamp (semi-definite, a zero second moment: a rod, a disc),
    // and an eigenprojection below could divide by a zero gap.
    Dp = D;
  } else if (d[1] >= 0.0) {
    Dp = D - d[2] * ((I - l[0] * One) * (I - l[1] * One)) / ((l[2] - l[0]) * (l[2] - l[1]));
  } else {
    Dp = d[0] * ((I - l[1] * One) * (I - l[2] * One)) / ((l[0] - l[1]) * (l[0] - l[2]));
  }
  return Dp.trace() * One - Dp;
}

Wrench tracker_noise(const Wrench& residual_rms, double sigma_force, double sigma_moment) {
  Wrench noise = (residual_rms.array() > 0).select(residual_rms, TrackerOptions{}.noise);
  if (sigma_force > 0) noise.head<3>().setConstant(sigma_force);
  if (sigma_moment > 0) noise.tail<3>().setConstant(sigma_moment);
  return noise;
}

const char* tracker_event_name(TrackerEvent event) {
  static const char* const names[] = {"", "change", "contact"};  // None, Change, Contact
  const auto i = static_cast<std::size_t>(event);
  return i < std::size(names) ? names[i] : "";
}

struct Tracker::Impl {
  IdentifiedModel identified;
  IdentifiedModelData data;
  KinematicsData kin;
  TrackerOptions options;
  int link = 0;
  bool dynamic = false;
  // A dynamic model with no joints is one rigid body on the sensor, so on
  // LINK: its wrench is Y_LINK theta_rigid (rigid_mechanism).
  bool rigid = false;
  Vector10 theta_rigid = Vector10::Zero();
  std::vector<double> zeros;  // [num_joints] qd = qdd = 0 for a static model

  Vector16 x = Vector16::Zero();
  Matrix16 P = Matrix16::Zero();
  Wrench noise_var = Wrench::Zero();  // R's diagonal
  Wrench noise_inv = Wrench::Zero();  // R^-1's diagonal
  Wrench walk_var = Wrench::Zero();   // per s
  Vector10 prior_var = Vector10::Zero();
  double last_t = std::numeric_limits<double>::quiet_NaN();

  std::vector<TrackerRow> ring;  // [kTrackerRing]
  long long count = -1;          // the latest row's index
  long long next_commit = 0;     // the next row the filter may learn from
  long long last_flagged = std::numeric_limits<long long>::min() / 2;
  int run = 0;  // flagged rows in a row, up to the latest

  TrackerEstimate estimate;

  Impl(const IdentifiedModel& m, const TrackerOptions& o)
      : identified(m), data(m), kin(m.model()), options(o) {}

  TrackerRow& row(long long i) { return ring[static_cast<std::size_t>(i % kTrackerRing)]; }

  // The work of one row (tracker_innovation, tracker_correct).
  struct Gain {
    Eigen::Matrix<double, kState, 6> PHt;  // P H^T, then G = P H^T L^-T
    Eigen::Matrix<double, 6, 6> L;         // L and D
    Wrench inv;                            // D^-1
    Wrench v;                              // L^-1 e
  };
  Gain gain;

  // d^2 = e^T S^-1 e of a row against the current state (gain filled).
  double innovation(const TrackerRow& r) {
    return detail::tracker_innovation(x.data(), P.data(), r.Y.data(), r.moving, r.z.data(),
                                      noise_var.data(), gain.PHt.data(), gain.L.data(),
                                      gain.inv.data(), gain.v.data());
  }

  // A row's e = z - H x against the current state (Y's inertia columns,
  // zero at rest, taken only in motion).
  Wrench residual(const TrackerRow& r) const {
    Wrench e = r.z - x.tail<6>();
    if (r.moving)
      e.noalias() -= r.Y * x.head<kPayload>();
    else
      e.noalias() -= r.Y.leftCols<kRestColumns>() * x.head<kRestColumns>();
    return e;
  }

  // The gate's d^2 of the newest row (TrackerOptions::exact_d2): S = H P H^T
  // + R >= R, so d^2 = e^T S^-1 e <= e^T R^-1 e, and a row within the gate by
  // that bound is within it by S: S is formed only for the rows beyond it.
  double gate_d2(const TrackerRow& r) {
    if (!options.exact_d2) {
      const Wrench e = residual(r);
      const double bound = (e.array().square() * noise_inv.array()).sum();
      if (bound <= options.gate) return bound;
    }
    return innovation(r);
  }

  // The Kalman filter's update with a row.
  void learn(const TrackerRow& r) {
    innovation(r);
    detail::tracker_correct(x.data(), P.data(), gain.PHt.data(), gain.L.data(), gain.inv.data(),
                            gain.v.data());
  }

  // A flagged row's share of the refit (TrackerRow::A, b, ee): the normal
  // equations axis by axis as outer products of Y's rows on the columns they
  // can have non-zero.
  void refit_share(TrackerRow& r) const {
    const Wrench e = residual(r);
    const Wrench& w = noise_inv;
    r.A.setZero();
    r.b.setZero();
    r.ee = 0.0;
    for (int k = 0; k < 6; ++k) {
      r.ee += e[k] * (w[k] * e[k]);
      if (k < 3 || !r.moving) {
        const Eigen::Vector4d y = r.Y.row(k).head<kRestColumns>().transpose();
        const Eigen::Vector4d u = w[k] * y;
        r.A.topLeftCorner<kRestColumns, kRestColumns>().noalias() += y * u.transpose();
        r.b.head<kRestColumns>() += u * e[k];
      } else {
        const Vector10 y = r.Y.row(k).transpose();
        const Vector10 u = w[k] * y;
        r.A.noalias() += y * u.transpose();
        r.b += u * e[k];
      }
    }
  }

  // A fresh rigid payload change fitted to the last `window` rows (the
  // offsets held): does it explain them to the noise? The rows' shares
  // (refit_share) summed: the run's rows are all flagged.
  bool rigid_change_explains() {
    const int n = options.window;
    Matrix10 A = Matrix10::Zero();
    Vector10 b = Vector10::Zero();
    double ee = 0.0;
    for (long long i = count - n + 1; i <= count; ++i) {
      const TrackerRow& r = row(i);
      if (r.moving) {
        A += r.A;
        b += r.b;
      } else {
        A.topLeftCorner<kRestColumns, kRestColumns>() +=
            r.A.topLeftCorner<kRestColumns, kRestColumns>();
        b.head<kRestColumns>() += r.b.head<kRestColumns>();
      }
      ee += r.ee;
    }
    Matrix10 Ar = A;
    Ar.diagonal() += prior_var.cwiseInverse();
    const Vector10 delta = Ar.ldlt().solve(b);
    const double residual = ee - 2.0 * b.dot(delta) + delta.dot(A * delta);
    const double dof = 6.0 * n - kPayload;
    return residual / dof < options.change_fit;
  }

  void restart_payload() {
    x.head<kPayload>().setZero();
    P.topRows<kPayload>().setZero();
    P.leftCols<kPayload>().setZero();
    P.topLeftCorner<kPayload, kPayload>().diagonal() = prior_var;
  }

  void write_estimate(const TrackerRow& r);

  void rigid_mechanism();
};

// A mechanism with no joints is rigid on the sensor, and whatever its links,
// it is one body: ten parameters in LINK's frame (the parallel-axis theorem
// and a rotation are linear in them), its wrench Y_LINK(w, dw, a) theta for
// any motion. theta is found once from the identified model's own
// predictor: least squares over random motions, kept only when it
// reproduces the predictor on as many others to round-off (1e-12 of the
// wrench); then update() needs no predictor call (about a tenth of it).
void Tracker::Impl::rigid_mechanism() {
  const Model& model = identified.model();
  if (!dynamic || model.num_joints() != 0) return;
  std::mt19937_64 rng(28);
  std::normal_distribution<double> N(0.0, 1.0);
  const auto motion = [&](Eigen::Vector3d& g, FrameMotion& sensor) {
    g = 9.81 * Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized();
    sensor = {Eigen::Vector3d(N(rng), N(rng), N(rng)),
              5.0 * Eigen::Vector3d(N(rng), N(rng), N(rng)),
              3.0 * Eigen::Vector3d(N(rng), N(rng), N(rng))};
  };
  const double none = 0.0;
  const Eigen::VectorXd empty(0);
  constexpr int kMotions = 4;
  Eigen::Matrix<double, 6 * kMotions, kPayload> A;
  Eigen::Matrix<double, 6 * kMotions, 1> b;
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < kMotions; ++k) {
      Eigen::Vector3d g;
      FrameMotion sensor;
      motion(g, sensor);
      forward_kinematics(model, kin, empty, empty, empty, g, sensor);
      A.middleRows<6>(6 * k) = link_regressor(kin, link);
      b.segment<6>(6 * k) = identified.predict(data, &none, &none, &none, g, sensor);
    }
    if (pass == 0) {
      theta_rigid = A.colPivHouseholderQr().solve(b);
    } else if ((A * theta_rigid - b).cwiseAbs().maxCoeff() <=
               1e-12 * (1.0 + b.cwiseAbs().maxCoeff())) {
      rigid = true;
    }
  }
}

void Tracker::Impl::write_estimate(const TrackerRow& r) {
  TrackerEstimate& out = estimate;
  const double m = x[0];
  out.mass = std::max(m, 0.0);
  out.mass_std = std::sqrt(std::max(P(0, 0), 0.0));
  const Eigen::Vector3d h = x.segment<3>(1);
  // The centre of mass h / m and its std (first order) once the mass is seen.
  if (out.mass > 3.0 * out.mass_std && out.mass > 0.0) {
    out.com = h / out.mass;
    Eigen::Matrix<double, 3, 4> J;
    J.col(0) = -h / (out.mass * out.mass);
    J.rightCols<3>() = Eigen::Matrix3d::Identity() / out.mass;
    const Eigen::Matrix3d C = J * P.topLeftCorner<4, 4>() * J.transpose();
    out.com_stds = C.diagonal().cwiseMax(0.0).cwiseSqrt();
  } else {
    out.com.setZero();
    out.com_stds = P.diagonal().segment<3>(1).cwiseMax(0.0).cwiseSqrt() /
                   std::max(std::max(out.mass, 3.0 * out.mass_std), 1e-12);
  }
  out.com_std = out.com_stds.maxCoeff();
  // The inertia about the centre of mass, projected: principal moments
  // l_k = d_i + d_j with the second moments d >= 0 (PSD and the triangle
  // inequalities).
  const double inertia_var = P.diagonal().segment<6>(kRestColumns).maxCoeff();
  out.inertia_determined = std::sqrt(std::max(inertia_var, 0.0)) <= options.inertia_determined;
  if (out.inertia_determined) {
    Eigen::Matrix3d I;
    I << x[4], x[5], x[6], x[5], x[7], x[8], x[6], x[8], x[9];
    const Eigen::Vector3d& c = out.com;
    I -= out.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    out.inertia = consistent_inertia(I);
  } else {
    out.inertia.setZero();
  }
  out.offset = x.tail<6>();
  out.offset_std = P.bottomRightCorner<6, 6>().diagonal().cwiseMax(0.0).cwiseSqrt();
  out.compensated = residual(r);
}

Tracker::Tracker(const IdentifiedModel& identified, const TrackerOptions& options) {
  const Model& model = identified.model();
  int link = -1;
  if (options.payload_link.empty()) {
    link = farthest_link(model);
  } else {
    link = model.find_link(options.payload_link);
    if (link < 0) {
      std::string names;
      for (const Link& l : model.links) names += (names.empty() ? "" : ", ") + l.name;
      throw InputError(fmt::format(
          "payload link '{}' is not a measured link of {} (sensor link '{}'); the measured links: "
          "{}",
          options.payload_link, model.source, model.sensor_link(), names));
    }
  }
  const auto positive = [](const Wrench& w) { return (w.array() > 0.0).all(); };
  if (!positive(options.noise) || !positive(options.offset_std) ||
      !(options.offset_walk.array() >= 0.0).all() || !(options.mass_std > 0) ||
      !(options.moment_std > 0) || !(options.inertia_std > 0) || !(options.gate > 0) ||
      options.lag < 0 || options.window < 2 || options.refit_every < 1 ||
      options.lag + options.window > kTrackerRing || !(options.change_fit > 1.0))
    throw ArgumentError(
        "massid::Tracker: options out of range (noise, offset_std, mass/moment/inertia_std and "
        "gate > 0; offset_walk >= 0; lag >= 0, window >= 2, lag + window <= kTrackerRing; "
        "change_fit > 1)");
  impl_ = std::make_unique<Impl>(identified, options);
  Impl& m = *impl_;
  m.link = link;
  m.dynamic = identified.dynamic();
  m.zeros.assign(static_cast<std::size_t>(std::max(1, model.num_joints())), 0.0);
  m.noise_var = options.noise.cwiseAbs2();
  m.noise_inv = m.noise_var.cwiseInverse();
  m.walk_var = options.offset_walk.cwiseAbs2();
  m.prior_var << options.mass_std, Eigen::Vector3d::Constant(options.moment_std),
      Eigen::Matrix<double, 6, 1>::Constant(options.inertia_std);
  m.prior_var = m.prior_var.cwiseAbs2();
  m.ring.resize(kTrackerRing);
  // The start: no payload (known), the identified offsets (or zero), uncertain.
  m.x.tail<6>() = identified.offset();
  m.P.topLeftCorner<kPayload, kPayload>().diagonal().setConstant(1e-12);
  m.P.bottomRightCorner<6, 6>().diagonal() = options.offset_std.cwiseAbs2();
  m.estimate.offset = m.x.tail<6>();
  m.rigid_mechanism();
}

Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

const TrackerEstimate& Tracker::estimate() const { return impl_->estimate; }
const IdentifiedModel& Tracker::identified() const { return impl_->identified; }
int Tracker::payload_link() const { return impl_->link; }
const std::string& Tracker::payload_link_name() const {
  return impl_->identified.model().links[static_cast<std::size_t>(impl_->link)].name;
}
Eigen::Matrix<double, 16, 1> Tracker::state() const { return impl_->x; }
Eigen::Matrix<double, 16, 16> Tracker::covariance() const { return impl_->P; }

const TrackerEstimate& Tracker::update(double t, const double* q, const double* qd,
                                       const double* qdd, const Eigen::Vector3d& gravity,
                                       const FrameMotion& sensor, const Wrench& measured) {
  Impl& m = *impl_;
  const TrackerOptions& o = m.options;
  if (!std::isfinite(t) || (std::isfinite(m.last_t) && !(t > m.last_t)))
    throw ArgumentError(fmt::format(
        "massid::Tracker::update: t = {} does not increase (the previous sample's is {})", t,
        m.last_t));
  const double dt = std::isfinite(m.last_t) ? t - m.last_t : 0.0;
  m.last_t = t;
  // The offsets' random walk.
  m.P.bottomRightCorner<6, 6>().diagonal() += m.walk_var * dt;

  // The mechanism's wrench and LINK's regressor, from the same joints.
  const Model& model = m.identified.model();
  const int n = model.num_joints();
  if (!m.dynamic || qd == nullptr || qdd == nullptr) qd = qdd = m.zeros.data();  // at rest
  using VectorMap = Eigen::Map<const Eigen::VectorXd>;
  forward_kinematics(model, m.kin, VectorMap(q, n), VectorMap(qd, n), VectorMap(qdd, n), gravity,
                     m.dynamic ? sensor : FrameMotion{});
  ++m.count;
  TrackerRow& r = m.row(m.count);
  r.Y = link_regressor(m.kin, m.link);
  const Wrench predicted = m.rigid ? Wrench(r.Y * m.theta_rigid)
                                   : m.identified.predict(m.data, q, qd, qdd, gravity, sensor);
  r.moving = (r.Y.rightCols<kPayload - kRestColumns>().array() != 0.0).any();
  r.z = measured - predicted;
  m.estimate.d2 = m.gate_d2(r);
  r.flagged = m.estimate.d2 > o.gate;
  m.estimate.event = TrackerEvent::None;
  if (r.flagged) {
    m.refit_share(r);
    ++m.run;
    m.last_flagged = m.count;
    m.estimate.event = TrackerEvent::Contact;
    if (m.run >= o.window && (m.run - o.window) % o.refit_every == 0 && m.rigid_change_explains()) {
      // A new load: the payload restarts and learns the run's last rows.
      m.restart_payload();
      for (long long i = m.count - o.window + 1; i <= m.count; ++i) {
        m.row(i).flagged = false;
        m.learn(m.row(i));
      }
      m.run = 0;
      m.last_flagged = m.count - o.window;
      m.next_commit = m.count + 1;
      m.estimate.event = TrackerEvent::Change;
    }
  } else {
    m.run = 0;
  }
  // Commit the row `lag` rows back when no row within `lag` either side is flagged.
  const long long j = m.count - o.lag;
  if (j >= m.next_commit) {
    if (m.last_flagged < j - o.lag) m.learn(m.row(j));
    m.next_commit = j + 1;
  }
  m.write_estimate(r);
  return m.estimate;
}

}  // namespace massid

#include "massid/live/tracker.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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

// The rows kept: LINK's regressor and the measured wrench less the
// mechanism's prediction, flagged when beyond the gate.
struct TrackerRow {
  Matrix6x10 Y = Matrix6x10::Zero();
  Wrench z = Wrench::Zero();
  bool flagged = false;
};

}  // namespace

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

Wrench tracker_noise(const Wrench& residual_rms, double sigma_force, double sigma_moment) {
  Wrench noise = TrackerOptions{}.noise;
  for (int k = 0; k < 6; ++k)
    if (residual_rms[k] > 0) noise[k] = residual_rms[k];
  if (sigma_force > 0) noise.head<3>().setConstant(sigma_force);
  if (sigma_moment > 0) noise.tail<3>().setConstant(sigma_moment);
  return noise;
}

const char* tracker_event_name(TrackerEvent event) {
  switch (event) {
    case TrackerEvent::Change:
      return "change";
    case TrackerEvent::Contact:
      return "contact";
    case TrackerEvent::None:
      break;
  }
  return "";
}

struct Tracker::Impl {
  IdentifiedModel identified;
  IdentifiedModelData data;
  KinematicsData kin;
  TrackerOptions options;
  int link = 0;
  bool dynamic = false;
  std::vector<double> zeros;  // [num_joints] qd = qdd = 0 for a static model

  Vector16 x = Vector16::Zero();
  Matrix16 P = Matrix16::Zero();
  Wrench noise_var = Wrench::Zero();  // R's diagonal
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

  // A row's innovation e, P H^T and the factor of S = H P H^T + R.
  using Innovation = Eigen::LLT<Eigen::Matrix<double, 6, 6>>;
  void innovation(const TrackerRow& r, Wrench& e, Eigen::Matrix<double, 16, 6>& PHt,
                  Innovation& llt) const {
    e = r.z - r.Y * x.head<kPayload>() - x.tail<6>();
    PHt.noalias() = P.leftCols<kPayload>() * r.Y.transpose();
    PHt += P.rightCols<6>();
    Eigen::Matrix<double, 6, 6> S = r.Y * PHt.topRows<kPayload>() + PHt.bottomRows<6>();
    S.diagonal() += noise_var;
    llt.compute(S);
  }

  // The Kalman filter's update with a row.
  void learn(const TrackerRow& r) {
    Wrench e;
    Eigen::Matrix<double, 16, 6> PHt;
    Innovation llt;
    innovation(r, e, PHt, llt);
    const Eigen::Matrix<double, 6, 16> Kt = llt.solve(PHt.transpose());  // K^T
    x.noalias() += Kt.transpose() * e;
    P.noalias() -= PHt * Kt;
    P = 0.5 * (P + P.transpose()).eval();
  }

  // d^2 = e^T S^-1 e of a row against the current state.
  double chi2(const TrackerRow& r) const {
    Wrench e;
    Eigen::Matrix<double, 16, 6> PHt;
    Innovation llt;
    innovation(r, e, PHt, llt);
    return e.dot(llt.solve(e));
  }

  // A fresh rigid payload change fitted to the last `window` rows (the
  // offsets held): does it explain them to the noise?
  bool rigid_change_explains() {
    const int n = options.window;
    Matrix10 A = Matrix10::Zero();
    Vector10 b = Vector10::Zero();
    double ee = 0.0;
    const Wrench w = noise_var.cwiseInverse();
    for (long long i = count - n + 1; i <= count; ++i) {
      const TrackerRow& r = row(i);
      const Wrench e = r.z - r.Y * x.head<kPayload>() - x.tail<6>();
      const Matrix6x10 WY = w.asDiagonal() * r.Y;
      A.noalias() += r.Y.transpose() * WY;
      b.noalias() += WY.transpose() * e;
      ee += e.dot(w.asDiagonal() * e);
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

  void write_estimate(const Wrench& measured_minus_mechanism, const Matrix6x10& Y);
};

void Tracker::Impl::write_estimate(const Wrench& z, const Matrix6x10& Y) {
  TrackerEstimate& out = estimate;
  const double m = x[0];
  out.mass = std::max(m, 0.0);
  out.mass_std = std::sqrt(std::max(P(0, 0), 0.0));
  const Eigen::Vector3d h = x.segment<3>(1);
  const Eigen::Matrix3d Phh = P.block<3, 3>(1, 1);
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
    out.com_stds = Phh.diagonal().cwiseMax(0.0).cwiseSqrt() /
                   std::max(std::max(out.mass, 3.0 * out.mass_std), 1e-12);
  }
  out.com_std = out.com_stds.maxCoeff();
  // The inertia about the centre of mass, projected: principal moments
  // l_k = d_i + d_j with the second moments d >= 0 (PSD and the triangle
  // inequalities).
  double inertia_std = 0.0;
  for (int k = 4; k < kPayload; ++k) inertia_std = std::max(inertia_std, P(k, k));
  out.inertia_determined = std::sqrt(inertia_std) <= options.inertia_determined;
  if (out.inertia_determined) {
    Eigen::Matrix3d I;
    I << x[4], x[5], x[6], x[5], x[7], x[8], x[6], x[8], x[9];
    const Eigen::Vector3d& c = out.com;
    I -= out.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(I);
    const Eigen::Vector3d l = eig.eigenvalues();
    const Eigen::Vector3d d = (Eigen::Vector3d::Constant(0.5 * l.sum()) - l).cwiseMax(0.0);
    const Eigen::Vector3d lp = Eigen::Vector3d::Constant(d.sum()) - d;
    out.inertia = eig.eigenvectors() * lp.asDiagonal() * eig.eigenvectors().transpose();
  } else {
    out.inertia.setZero();
  }
  out.offset = x.tail<6>();
  out.offset_std = P.bottomRightCorner<6, 6>().diagonal().cwiseMax(0.0).cwiseSqrt();
  out.compensated = z - Y * x.head<kPayload>() - x.tail<6>();
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
}

Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

const TrackerEstimate& Tracker::estimate() const { return impl_->estimate; }
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
  const double* z0 = m.zeros.data();
  const bool motion = m.dynamic && qd != nullptr && qdd != nullptr;
  const Wrench predicted = m.identified.predict(m.data, n > 0 ? q : z0, motion ? qd : z0,
                                                motion ? qdd : z0, gravity, sensor);
  using VectorMap = Eigen::Map<const Eigen::VectorXd>;
  forward_kinematics(model, m.kin, VectorMap(n > 0 ? q : z0, n), VectorMap(motion ? qd : z0, n),
                     VectorMap(motion ? qdd : z0, n), gravity, m.dynamic ? sensor : FrameMotion{});

  ++m.count;
  TrackerRow& r = m.row(m.count);
  r.Y = link_regressor(m.kin, m.link);
  r.z = measured - predicted;
  m.estimate.d2 = m.chi2(r);
  r.flagged = m.estimate.d2 > o.gate;
  m.estimate.event = TrackerEvent::None;
  if (r.flagged) {
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
  m.write_estimate(r.z, r.Y);
  return m.estimate;
}

}  // namespace massid

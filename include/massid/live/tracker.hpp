// Online tracking of a payload and of the sensor's drifting offsets, one
// sample at a time (`massid compensate --track`; docs/tracking.md).
//
// The payload is one rigid body on LINK, in addition to what the identified
// model holds, zero at the start. Its ten parameters pi = (m, h = m c, I_O:
// ixx ixy ixz iyy iyz izz about LINK's origin in LINK's axes) enter the
// measured wrench through LINK's regressor (link_regressor, regressor.hpp):
// 4 columns matter at rest (m, h), all 10 in motion. The state
//
//   x = [pi (10), offset (6)],   measured - predicted(mechanism) = [Y_LINK  1] x + v
//
// is estimated by a Kalman filter: the payload constant, the offsets a random
// walk (options.offset_walk, per sqrt(s)), v the sensor noise
// (options.noise). Each row:
//  - its innovation e and covariance S = H P H^T + R give d^2 = e^T S^-1 e;
//    a row with d^2 beyond the gate (chi^2, 6 dof) is flagged (S >= R, so a
//    row within the gate by e^T R^-1 e needs no S: TrackerOptions::exact_d2);
//  - rows are committed to the filter `lag` rows late, and only when no row
//    within `lag` rows either side is flagged, so that the ramps at the edges
//    of a contact, below the gate, teach it nothing;
//  - a run of `window` flagged rows is refitted: a fresh rigid payload (ten
//    parameters, the offsets held) fitted to the run's last `window` rows. If
//    it explains them to the noise (chi^2 test), the load changed (`change`):
//    the payload restarts (large covariance, offsets kept) and the run's rows
//    are fed to it; else the rows carry an external wrench (`contact`).
// What it cannot tell apart (docs/tracking.md): at rest, a contact force
// along gravity with its moment perpendicular to it is a weight; a load
// change made while the arm moves fast is refitted like any other run.
//
// The written estimate is physically consistent at every row (mass >= 0, the
// inertia about the centre of mass positive semi-definite and within the
// triangle inequalities, by projection); its std come from the filter's
// covariance. No allocation after construction. A dynamic model with no
// joints (a tool rigid on the sensor) is one body on LINK: its wrench is
// Y_LINK theta, theta fitted once from its predictor and checked to round-off.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "massid/core/kinematics.hpp"
#include "massid/core/predictor.hpp"
#include "massid/live/identified_model.hpp"

namespace massid {

struct TrackerOptions {
  // The payload's link: "" for the measured link farthest from the sensor
  // (most joints away; the last such in the model's order).
  std::string payload_link;
  // Sensor noise, std per axis (N, N m).
  Wrench noise = (Wrench() << 0.05, 0.05, 0.05, 0.003, 0.003, 0.003).finished();
  // The offsets' random walk, std growth per sqrt(s) (N, N m).
  Wrench offset_walk = (Wrench() << 0.005, 0.005, 0.005, 0.00025, 0.00025, 0.00025).finished();
  // The offsets' std at the start: the identified model's offsets (or zero)
  // are that uncertain (N, N m).
  Wrench offset_std = (Wrench() << 10.0, 10.0, 10.0, 1.0, 1.0, 1.0).finished();
  // A new payload's prior std: mass kg, first moment kg m, inertia kg m^2.
  double mass_std = 50.0, moment_std = 5.0, inertia_std = 1.0;
  // Rows: flagged beyond this chi^2 (6 dof) of the innovation; committed
  // `lag` rows late; refitted after `window` flagged rows in a run (and every
  // `refit_every` rows after). window <= kTrackerRing - lag.
  double gate = 25.0;  // P(chi^2_6 > 25) = 3.4e-4
  int lag = 16;
  int window = 48;
  int refit_every = 4;
  // A refit explains the run when its residual chi^2 per degree of freedom is
  // below this.
  double change_fit = 1.5;
  // The inertia is written once the largest std of its six parameters is
  // below this, kg m^2.
  double inertia_determined = 2e-4;
  // TrackerEstimate::d2 exactly on every row. Otherwise (the default) a row
  // whose innovation is within the gate by the noise alone, e^T R^-1 e <=
  // gate, reports that bound: S = H P H^T + R >= R gives d^2 <= e^T R^-1 e,
  // so the row is within the gate by S too and S is not formed (the same
  // flags, the same estimates; about a fifth of the update's time).
  bool exact_d2 = false;
};

// Rows kept for the lag and the refit.
constexpr int kTrackerRing = 128;

enum class TrackerEvent { None, Change, Contact };

// The estimate after a row, physically consistent.
struct TrackerEstimate {
  double mass = 0.0, mass_std = 0.0;                   // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();       // LINK's frame, m (0 while the mass is 0)
  Eigen::Vector3d com_stds = Eigen::Vector3d::Zero();  // per coordinate, m
  double com_std = 0.0;                                // the largest of the three, m
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();   // about the com, LINK's axes, kg m^2
  bool inertia_determined = false;
  Wrench offset = Wrench::Zero();
  Wrench offset_std = Wrench::Zero();
  TrackerEvent event = TrackerEvent::None;
  // The row's innovation chi^2 e^T S^-1 e against the state before it (6
  // dof), flagged beyond options.gate; a row within the gate by the noise
  // alone reports that bound e^T R^-1 e (>= d^2) unless options.exact_d2.
  double d2 = 0.0;
  Wrench compensated = Wrench::Zero();  // measured - predicted(mechanism, payload) - offset
};

class Tracker {
 public:
  // InputError: payload_link is no measured link of the model (names them);
  // ArgumentError: options out of range.
  explicit Tracker(const IdentifiedModel& identified, const TrackerOptions& options = {});
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;

  // One sample: t (s, increasing), the joints as IdentifiedModel::predict
  // takes them (qd, qdd: num_joints values each, read only for a dynamic
  // model; may be null for a static one), gravity and the sensor's motion in
  // the sensor frame, the measured wrench. Returns the estimate after it
  // (valid until the next call). No allocation. ArgumentError (the tracker
  // left as it was): t is not finite or does not increase.
  const TrackerEstimate& update(double t, const double* q, const double* qd, const double* qdd,
                                const Eigen::Vector3d& gravity, const FrameMotion& sensor,
                                const Wrench& measured);

  const TrackerEstimate& estimate() const;
  const IdentifiedModel& identified() const;  // the tracker's own copy
  int payload_link() const;                   // index in the model's links
  const std::string& payload_link_name() const;
  // The filter's raw state [pi (10), offset (6)] and covariance (unprojected).
  Eigen::Matrix<double, 16, 1> state() const;
  Eigen::Matrix<double, 16, 16> covariance() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The columns compensate --track appends after fx_comp..mz_comp (interface.md).
inline constexpr const char* kTrackerColumns[] = {
    "payload_m",     "payload_cx",  "payload_cy",  "payload_cz",  "payload_m_std",
    "payload_c_std", "payload_ixx", "payload_ixy", "payload_ixz", "payload_iyy",
    "payload_iyz",   "payload_izz", "offset_fx",   "offset_fy",   "offset_fz",
    "offset_mx",     "offset_my",   "offset_mz",   "event"};

// The inertia about the centre of mass a body can have that is nearest to I
// (symmetric, kg m^2): its second moments d = tr(I)/2 - eig(I) clamped at
// zero (positive semi-definite, within the triangle inequalities; I itself
// when it is). The tracker's written inertia.
Eigen::Matrix3d consistent_inertia(const Eigen::Matrix3d& I);

// "", "change", "contact"
const char* tracker_event_name(TrackerEvent event);

// The measured link farthest from the sensor: most joints between them (the
// last such in the model's order).
int farthest_link(const Model& model);

// The sensor noise every door tracks with (compensate --track, massid.h's
// massid_tracker_create, Python's massid.Tracker), std per axis: sigma_force
// (N) and sigma_moment (N m) where given (> 0), else the identification's
// residual RMS per axis where it has one (> 0: IdentifiedModel::residual_rms,
// the params file's "residual_rms"), else TrackerOptions' default.
Wrench tracker_noise(const Wrench& residual_rms, double sigma_force = 0.0,
                     double sigma_moment = 0.0);

}  // namespace massid

// The payload and offset tracker (tracker.hpp) on simulated logs of the
// UR-like arm: the wrench comes from the project's simulator
// (simulate_wrenches, dynamic) for the arm's own URDF and for a copy of it
// with an extra fixed link holding the object, so the truth never goes
// through the tracker's regressor code; the drifting offsets, the contact
// (a world-fixed force at the tool's tip) and the noise are added here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "massid/live/tracker.hpp"
#include "test_support.hpp"
#include "tracker_support.hpp"

namespace massid {
namespace {

using namespace tracker_test;

struct TrackerRun {
  std::vector<TrackerEstimate> rows;
};

TrackerRun track(const TrackerLog& log, const TrackerOptions& options = {}) {
  const IdentifiedModel model = tracker_identified(log);
  Tracker tracker(model, options);
  EXPECT_EQ(tracker.payload_link_name(), "tool");
  const Samples& s = log.samples;
  TrackerRun run;
  run.rows.reserve(static_cast<std::size_t>(s.size()));
  Eigen::VectorXd q, qd, qdd;
  double seconds = 0.0;
  for (int i = 0; i < s.size(); ++i) {
    q = s.q.row(i).transpose();
    qd = s.qd.row(i).transpose();
    qdd = s.qdd.row(i).transpose();
    FrameMotion sensor;
    if (s.has_sensor_motion()) {
      const auto m = s.sensor_motion.row(i);
      sensor = {m.segment<3>(0).transpose(), m.segment<3>(3).transpose(),
                m.segment<3>(6).transpose()};
    }
    const Eigen::Vector3d g = s.gravity.row(i).transpose();
    const Wrench w = s.wrench.row(i).transpose();
    const auto t0 = std::chrono::steady_clock::now();
    const TrackerEstimate& e =
        tracker.update(s.time[i], q.data(), qd.data(), qdd.data(), g, sensor, w);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.rows.push_back(e);
  }
  std::cout << fmt::format("tracker: {:.2f} us per update ({} links)\n", 1e6 * seconds / s.size(),
                           log.plain.num_links());
  return run;
}

bool tracker_consistent(const TrackerEstimate& e) {
  if (!(e.mass >= 0.0) || !std::isfinite(e.mass_std) || !std::isfinite(e.com_std)) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(e.inertia);
  const Eigen::Vector3d l = eig.eigenvalues();
  const double tol = 1e-12;
  return l.minCoeff() >= -tol && l[0] + l[1] >= l[2] - tol && l[0] + l[2] >= l[1] - tol &&
         l[1] + l[2] >= l[0] - tol;
}

// Every issue-28 acceptance figure that one log shows.
void expect_tracked(const TrackerLog& log, const TrackerRun& run) {
  const Samples& s = log.samples;
  int changes = 0, contact_rows = 0, contact_flagged = 0, free_rows = 0, free_flagged = 0;
  double worst_mass = 0, worst_zero = 0, worst_com = 0, worst_f = 0, worst_m = 0;
  double worst_inertia = 0;
  int undetermined = 0;
  for (int i = 0; i < s.size(); ++i) {
    const double t = s.time[i];
    const TrackerEstimate& e = run.rows[static_cast<std::size_t>(i)];
    ASSERT_TRUE(tracker_consistent(e)) << "t = " << t;
    if (e.event == TrackerEvent::Change) {
      ++changes;
      EXPECT_TRUE((t > kGrasp && t < kGrasp + 0.3) || (t > kRelease && t < kRelease + 0.3))
          << "a change at t = " << t;
    }
    const bool flagged = e.event == TrackerEvent::Contact;
    const bool near_change =
        (t >= kGrasp && t < kGrasp + 0.3) || (t >= kRelease && t < kRelease + 0.3);
    if (tracker_in_contact(t)) {
      ++contact_rows;
      contact_flagged += flagged;
    } else if (!near_change) {
      ++free_rows;
      free_flagged += flagged;
    }
    if (t >= kGrasp + 1.0 && t < kRelease)
      worst_mass = std::max(worst_mass, std::abs(e.mass - kObjectMass) / kObjectMass);
    if (t >= kRelease + 1.0) worst_zero = std::max(worst_zero, e.mass / kObjectMass);
    if (t >= kMotion[1].a + 1.5 && t < kRelease)
      worst_com = std::max(worst_com, (e.com - kObjectCom).norm());
    // The principal moments, 3 s into the motion after the grasp.
    if (t >= kMotion[1].a + 3.0 && t < kRelease) {
      if (!e.inertia_determined) ++undetermined;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(e.inertia);
      Eigen::Vector3d truth = kObjectInertia;
      std::sort(truth.data(), truth.data() + 3);
      worst_inertia = std::max(
          worst_inertia, ((eig.eigenvalues() - truth).array() / truth.array()).abs().maxCoeff());
    }
    if (t >= 5.0) {
      const Wrench d = e.offset - tracker_offset(t);
      worst_f = std::max(worst_f, d.head<3>().cwiseAbs().maxCoeff());
      worst_m = std::max(worst_m, d.tail<3>().cwiseAbs().maxCoeff());
    }
  }
  std::cout << fmt::format(
      "tracker: {} changes; worst mass error {:.3g} %, after release {:.3g} %, com {:.3g} mm, "
      "offsets {:.3g} N {:.3g} N m; contact rows flagged {}/{}, free rows {}/{}; principal "
      "moments {:.3g} %\n",
      changes, 100 * worst_mass, 100 * worst_zero, 1e3 * worst_com, worst_f, worst_m,
      contact_flagged, contact_rows, free_flagged, free_rows, 100 * worst_inertia);
  EXPECT_EQ(changes, 2);
  EXPECT_LT(worst_mass, 0.01);
  EXPECT_LT(worst_zero, 0.01);
  EXPECT_LT(worst_com, 0.002);
  EXPECT_LT(worst_f, 0.08);
  EXPECT_LT(worst_m, 0.004);
  EXPECT_GE(contact_flagged, 0.9 * contact_rows);
  EXPECT_LE(free_flagged, 0.01 * free_rows);
  EXPECT_EQ(undetermined, 0);
  EXPECT_LT(worst_inertia, 0.10);
}

TEST(Tracker, WristSensorTracksGraspDriftContactAndRelease) {
  const TrackerLog log = tracker_log(true, 1);
  expect_tracked(log, track(log));
}

TEST(Tracker, BaseSensorTracksGraspDriftContactAndRelease) {
  const TrackerLog log = tracker_log(false, 2);
  expect_tracked(log, track(log));
}

// Honest std: the mass (at rest after the grasp, and in motion) and the
// centre of mass (in motion) standardised by their std, over 50 seeds, for a
// wrist and for a base sensor: each RMS within 0.7 .. 1.5 (issue 28).
void expect_honest_std(bool wrist) {
  double mass_sum = 0, com_sum = 0;
  int mass_n = 0, com_n = 0;
  for (std::uint64_t seed = 100; seed < 150; ++seed) {
    const TrackerLog log = tracker_log(wrist, seed);
    const TrackerRun run = track(log);
    for (const double t : {kGrasp + 1.5, 15.0, 21.0}) {
      const TrackerEstimate& e = run.rows[static_cast<std::size_t>(std::lround(t * kRate))];
      const double zm = (e.mass - kObjectMass) / e.mass_std;
      mass_sum += zm * zm;
      ++mass_n;
      if (t < kMotion[1].a) continue;  // the com along gravity is unseen at rest
      for (int k = 0; k < 3; ++k) {
        const double zc = (e.com[k] - kObjectCom[k]) / e.com_stds[k];
        com_sum += zc * zc;
        ++com_n;
      }
    }
  }
  const double mass_rms = std::sqrt(mass_sum / mass_n), com_rms = std::sqrt(com_sum / com_n);
  std::cout << fmt::format(
      "tracker ({} sensor): standardised errors' RMS: mass {:.3f} over {} values, centre of "
      "mass {:.3f} over {} values\n",
      wrist ? "wrist" : "base", mass_rms, mass_n, com_rms, com_n);
  EXPECT_GT(mass_rms, 0.7);
  EXPECT_LT(mass_rms, 1.5);
  EXPECT_GT(com_rms, 0.7);
  EXPECT_LT(com_rms, 1.5);
}

TEST(Tracker, StandardisedErrorsOverFiftySeedsWristSensor) { expect_honest_std(true); }
TEST(Tracker, StandardisedErrorsOverFiftySeedsBaseSensor) { expect_honest_std(false); }

// A contact at rest, horizontal: no weight can explain it, so it is contact
// throughout, and the payload (none) and offsets are untouched.
TEST(Tracker, HorizontalPushAtRestIsContactNotALoad) {
  TrackerLog log = tracker_log(true, 21, false);
  Samples& s = log.samples;
  const Eigen::Matrix3d R = upstream_kinematics(log.plain, s.q_upstream.row(0).transpose(),
                                                Eigen::VectorXd(), Eigen::VectorXd())
                                .rotation;
  const Eigen::Vector3d F = R.transpose() * Eigen::Vector3d(8.0, -5.0, 0.0);
  int rows = 0;
  for (int i = 0; i < s.size(); ++i)
    if (s.time[i] >= 1.0 && s.time[i] < 2.5) {  // at rest
      s.wrench.block<1, 3>(i, 0) += F.transpose();
      ++rows;
    }
  const TrackerRun run = track(log);
  int flagged = 0, changes = 0;
  for (int i = 0; i < s.size(); ++i) {
    const TrackerEstimate& e = run.rows[static_cast<std::size_t>(i)];
    changes += e.event == TrackerEvent::Change;
    if (s.time[i] >= 1.0 && s.time[i] < 2.5) flagged += e.event == TrackerEvent::Contact;
    EXPECT_LT(e.mass, 0.01) << s.time[i];
  }
  EXPECT_EQ(changes, 0);
  EXPECT_EQ(flagged, rows);
}

// A static params file (first moments, identified at rest) tracks the 4
// parameters a rest log shows: a wrist log of poses held 1 s each (no
// velocities), the object grasped during the third. The mass from the pose
// it is grasped at, the whole centre of mass once gravity has turned; the
// inertia never written.
TEST(Tracker, StaticParamsTrackMassAndCentreOfMassFromRestPoses) {
  const std::string urdf = test::examples()[1].urdf;
  const Model wrist = load_urdf(urdf, "wrist_3_link");
  const Model with = load_urdf_string(object_urdf(urdf), "wrist_3_link", "ur_like+object");
  const double rate = 200.0, hold = 1.0, grasp = 2.5;
  const int poses = 12, per = static_cast<int>(hold * rate), n = poses * per;
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> U(-2.5, 2.5);
  Samples s;
  s.source = "rest";
  s.q.resize(n, 0);
  s.q_upstream.resize(n, 6);
  s.gravity.resize(n, 3);
  s.gravity_from_upstream = true;
  s.time.resize(n);
  s.line.resize(static_cast<std::size_t>(n));
  Eigen::VectorXd q(6);
  for (int i = 0; i < n; ++i) {
    if (i % per == 0)
      for (int j = 0; j < 6; ++j) q[j] = U(rng);
    s.q_upstream.row(i) = q.transpose();
    s.time[i] = i / rate;
    s.line[static_cast<std::size_t>(i)] = i + 2;
  }
  resolve_upstream(wrist, s);
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.003;
  so.seed = 32;
  const Eigen::MatrixXd w0 = simulate_wrenches(wrist, s, so);
  so.seed = 33;
  const Eigen::MatrixXd w1 = simulate_wrenches(with, s, so);
  const BaseParameters base = find_base_parameters(wrist);
  ASSERT_FALSE(base.motion());
  const IdentifiedModel model = IdentifiedModel::from_values(
      wrist, base, base.K * ParameterLayout::first_moments().nominal(wrist));
  Tracker tracker(model);
  int changes = 0, written = 0;
  double worst_mass = 0, worst_com = 0;
  for (int i = 0; i < n; ++i) {
    const double t = s.time[i];
    const Wrench w = (t >= grasp ? w1 : w0).row(i).transpose();
    const TrackerEstimate& e =
        tracker.update(t, nullptr, nullptr, nullptr, s.gravity.row(i).transpose(), {}, w);
    ASSERT_TRUE(tracker_consistent(e));
    written += t >= grasp + 0.5 && e.inertia_determined;  // the payload known zero before
    changes += e.event == TrackerEvent::Change;
    if (t >= grasp + 1.0)
      worst_mass = std::max(worst_mass, std::abs(e.mass - kObjectMass) / kObjectMass);
    if (t >= 6.0) worst_com = std::max(worst_com, (e.com - kObjectCom).norm());
  }
  EXPECT_EQ(changes, 1);
  EXPECT_EQ(written, 0);
  EXPECT_LT(worst_mass, 0.01);
  EXPECT_LT(worst_com, 0.002);
}

TEST(Tracker, PayloadLinkDefaultsToTheFarthestAndUnknownLinksAreNamed) {
  const TrackerLog log = tracker_log(true, 3);
  const IdentifiedModel model = tracker_identified(log);
  EXPECT_EQ(Tracker(model).payload_link_name(), "tool");
  TrackerOptions o;
  o.payload_link = "wrist_3_link";
  EXPECT_EQ(Tracker(model, o).payload_link_name(), "wrist_3_link");
  o.payload_link = "gripper";
  try {
    Tracker bad(model, o);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'gripper'"), std::string::npos) << m;
    EXPECT_NE(m.find("tool"), std::string::npos) << m;
  }
}

// The update's arithmetic (the structured kernels: H = [Y | I6] with Y's zero
// columns skipped, S = L D L^T, P -= G G^T) against the textbook Kalman
// filter in dense Eigen, Joseph form, on a tracked log at rest and in motion:
// with no gate and no lag the tracker is that filter, row for row. State,
// covariance and d^2 to round-off.
TEST(Tracker, UpdateIsTheTextbookKalmanFilterToRoundOff) {
  const TrackerLog log = tracker_log(true, 4);
  const IdentifiedModel model = tracker_identified(log);
  TrackerOptions o;
  o.lag = 0;
  o.gate = 1e300;  // nothing flagged: every row learnt as it comes
  o.exact_d2 = true;
  Tracker tracker(model, o);
  Eigen::Matrix<double, 16, 1> x = tracker.state();
  Eigen::Matrix<double, 16, 16> P = tracker.covariance();
  const Wrench walk = o.offset_walk.cwiseAbs2(), noise = o.noise.cwiseAbs2();
  IdentifiedModelData data(model);
  KinematicsData kin(model.model());
  const Samples& s = log.samples;
  const Eigen::VectorXd none(0);
  int checked = 0, moving = 0;
  double worst_x = 0, worst_P = 0, worst_d2 = 0;
  for (int i = 0; i < s.size(); ++i) {
    const auto m = s.sensor_motion.row(i);
    const FrameMotion sensor{m.segment<3>(0).transpose(), m.segment<3>(3).transpose(),
                             m.segment<3>(6).transpose()};
    const Eigen::Vector3d g = s.gravity.row(i).transpose();
    const Wrench w = s.wrench.row(i).transpose();
    const double none_value = 0.0;
    const TrackerEstimate& e =
        tracker.update(s.time[i], &none_value, &none_value, &none_value, g, sensor, w);
    // The textbook: the offsets' random walk, then the row.
    if (i > 0) P.diagonal().tail(6) += walk * (s.time[i] - s.time[i - 1]);
    forward_kinematics(model.model(), kin, none, none, none, g, sensor);
    const Eigen::Matrix<double, 6, 10> Y = link_regressor(kin, tracker.payload_link());
    moving += !Y.rightCols<6>().isZero(0.0);
    const Wrench z = w - model.predict(data, &none_value, &none_value, &none_value, g, sensor);
    Eigen::Matrix<double, 6, 16> H;
    H << Y, Eigen::Matrix<double, 6, 6>::Identity();
    const Wrench r = z - H * x;
    const Eigen::Matrix<double, 6, 6> S =
        H * P * H.transpose() + Eigen::Matrix<double, 6, 6>(noise.asDiagonal());
    const Eigen::Matrix<double, 16, 6> K = P * H.transpose() * S.inverse();
    const Eigen::Matrix<double, 16, 16> A = Eigen::Matrix<double, 16, 16>::Identity() - K * H;
    const double d2 = r.dot(S.inverse() * r);
    x += K * r;
    P = A * P * A.transpose() + K * noise.asDiagonal() * K.transpose();
    worst_d2 = std::max(worst_d2, std::abs(e.d2 - d2) / std::max(1.0, d2));
    if (i % 97 != 0 && i + 1 != s.size()) continue;
    ++checked;
    const Eigen::Matrix<double, 16, 1> tx = tracker.state();
    const Eigen::Matrix<double, 16, 16> tP = tracker.covariance();
    EXPECT_EQ(tP, tP.transpose()) << "t = " << s.time[i];  // exactly symmetric
    const Eigen::Matrix<double, 16, 1> sd = P.diagonal().cwiseSqrt();
    for (int a = 0; a < 16; ++a) {
      worst_x = std::max(worst_x, std::abs(tx[a] - x[a]) / sd[a]);
      for (int b = 0; b < 16; ++b)
        worst_P = std::max(worst_P, std::abs(tP(a, b) - P(a, b)) / (sd[a] * sd[b]));
    }
  }
  std::cout << fmt::format(
      "tracker against the textbook filter: {} rows ({} in motion), worst state {:.2g} std, "
      "covariance {:.2g}, d2 {:.2g}\n",
      s.size(), moving, worst_x, worst_P, worst_d2);
  EXPECT_GT(moving, s.size() / 3);
  EXPECT_LT(moving, s.size());
  EXPECT_GT(checked, 200);
  EXPECT_LT(worst_x, 1e-7);
  EXPECT_LT(worst_P, 1e-7);
  EXPECT_LT(worst_d2, 1e-7);
}

// The gate's shortcut (TrackerOptions::exact_d2 false, the default): a row
// whose noise-only bound e^T R^-1 e is within the gate is not checked against
// S. Since S >= R that bound is never below d^2, so the flags, the events and
// every estimate are those of the exact gate, bit for bit, on the 40 s logs
// with a grasp, a release, drift and a contact (a wrist and a base sensor);
// the reported d2 is the exact one beyond the gate and at least it below.
TEST(Tracker, GateShortcutByTheNoiseBoundChangesNoFlagNorEstimate) {
  for (const bool wrist : {true, false}) {
    const TrackerLog log = tracker_log(wrist, 7);
    TrackerOptions exact;
    exact.exact_d2 = true;
    const TrackerRun a = track(log), b = track(log, exact);
    ASSERT_EQ(a.rows.size(), b.rows.size());
    int beyond = 0, below = 0, contact = 0, changes = 0;
    for (std::size_t i = 0; i < a.rows.size(); ++i) {
      const TrackerEstimate &p = a.rows[i], &q = b.rows[i];
      ASSERT_EQ(p.event, q.event) << "row " << i;
      contact += q.event == TrackerEvent::Contact;
      changes += q.event == TrackerEvent::Change;
      EXPECT_EQ(p.mass, q.mass);
      EXPECT_EQ(p.com, q.com);
      EXPECT_EQ(p.com_stds, q.com_stds);
      EXPECT_EQ(p.inertia, q.inertia);
      EXPECT_EQ(p.offset, q.offset);
      EXPECT_EQ(p.offset_std, q.offset_std);
      EXPECT_EQ(p.compensated, q.compensated);
      if (p.d2 > TrackerOptions{}.gate) {
        ++beyond;
        EXPECT_EQ(p.d2, q.d2) << "row " << i;
      } else {
        ++below;
        EXPECT_GE(p.d2, q.d2 * (1 - 1e-12)) << "row " << i;
      }
    }
    // Both kinds of rows and both events were there to compare.
    EXPECT_GT(beyond, 500) << (wrist ? "wrist" : "base");
    EXPECT_GT(below, 10000);
    EXPECT_GT(contact, 500);
    EXPECT_EQ(changes, 2);
  }
}

// A tool rigid on a wrist sensor (a dynamic model with no joints) is one
// body on LINK: the tracker predicts its wrench as Y_LINK theta with theta
// fitted once from the model's predictor, not through the predictor on every
// row. On 300 random motions and gravities, a fresh tracker's first
// compensated wrench (no payload yet, the identified offsets) is the
// measured wrench less IdentifiedModel::predict and the offsets to round-off.
TEST(Tracker, RigidToolOnTheSensorIsOneBodyOnTheLinkAsThePredictorSays) {
  const TrackerLog log = tracker_log(true, 8);
  const IdentifiedModel model = tracker_identified(log);
  ASSERT_TRUE(model.dynamic());
  ASSERT_EQ(model.num_joints(), 0);
  IdentifiedModelData data(model);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> N(0.0, 1.0);
  const auto v3 = [&](double s) { return Eigen::Vector3d(s * N(rng), s * N(rng), s * N(rng)); };
  const double none = 0.0;
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d g = 9.80665 * v3(1.0).normalized();
    const FrameMotion sensor{v3(k % 3 == 0 ? 0.0 : 2.0), v3(k % 3 == 0 ? 0.0 : 8.0),
                             v3(k % 3 == 0 ? 0.0 : 4.0)};
    Wrench w;
    w << v3(20.0), v3(2.0);
    Tracker tracker(model);
    const Wrench c = tracker.update(0.0, &none, &none, &none, g, sensor, w).compensated;
    const Wrench expected =
        w - model.predict(data, &none, &none, &none, g, sensor) - model.offset();
    worst = std::max(worst, (c - expected).cwiseAbs().maxCoeff() / (1.0 + w.cwiseAbs().maxCoeff()));
  }
  std::cout << fmt::format("rigid tool as one body: worst difference {:.2g} of the wrench\n",
                           worst);
  EXPECT_LT(worst, 1e-12);
}

// The Compensator times the tracker's update only when asked (--stats):
// without it no tracked line reads the clock and tracker_update_ns() stays 0.
TEST(Tracker, CompensatorTimesTheUpdateOnlyWithStats) {
  const TrackerLog log = tracker_log(true, 6);
  const IdentifiedModel identified = tracker_identified(log);
  const std::string csv = tracker_csv(log, load_urdf(test::examples()[1].urdf));
  for (const bool timed : {false, true}) {
    CompensatorOptions o;
    o.track = true;
    o.time_tracker = timed;
    std::size_t at = csv.find('\n');
    Compensator comp(identified, std::string_view(csv).substr(0, at), "test", o);
    long long total = 0;
    for (int k = 0; k < 200; ++k) {
      const std::size_t next = csv.find('\n', at + 1);
      comp.compensate(std::string_view(csv).substr(at + 1, next - at - 1), k + 2);
      total += comp.tracker_update_ns();
      at = next;
    }
    if (timed)
      EXPECT_GT(total, 0);
    else
      EXPECT_EQ(total, 0);
  }
}

// The written inertia's projection against the textbook one with
// eigenvectors (second moments clamped at zero, moments rebuilt), on random
// symmetric matrices, a solid body (unchanged), and the bodies whose second
// moments have exact zeros: a rod and a disc are their own projection (the
// eigenprojection formula divided by a zero gap there: NaN written).
TEST(Tracker, ConsistentInertiaIsTheNearestBodyAndKeepsRodsAndDiscs) {
  const auto textbook = [](const Eigen::Matrix3d& I) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
    const Eigen::Vector3d l = eig.eigenvalues();
    const Eigen::Vector3d d = (Eigen::Vector3d::Constant(0.5 * l.sum()) - l).cwiseMax(0.0);
    const Eigen::Vector3d lp = Eigen::Vector3d::Constant(d.sum()) - d;
    return Eigen::Matrix3d(eig.eigenvectors() * lp.asDiagonal() * eig.eigenvectors().transpose());
  };
  std::mt19937_64 rng(11);
  std::normal_distribution<double> N(0.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    Eigen::Matrix3d A;
    for (int k = 0; k < 9; ++k) A(k / 3, k % 3) = N(rng);
    const Eigen::Matrix3d I = 1e-3 * (A + A.transpose());
    EXPECT_LT((consistent_inertia(I) - textbook(I)).norm(), 1e-12 * (1e-3 + I.norm())) << I;
  }
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (const Eigen::Vector3d& moments :
       {Eigen::Vector3d(2e-3, 1.5e-3, 1e-3), Eigen::Vector3d(0.0, 1e-3, 1e-3),
        Eigen::Vector3d(1e-3, 1e-3, 2e-3), Eigen::Vector3d(0.0, 0.0, 0.0)}) {
    for (const Eigen::Matrix3d& turn : {Eigen::Matrix3d(Eigen::Matrix3d::Identity()), R}) {
      const Eigen::Matrix3d I = turn * moments.asDiagonal() * turn.transpose();
      const Eigen::Matrix3d P = consistent_inertia(I);
      ASSERT_TRUE(P.allFinite()) << moments.transpose();
      EXPECT_LT((P - I).norm(), 1e-15) << moments.transpose();
    }
  }
  // Not a body (one moment beyond the sum of the others): projected to one.
  const Eigen::Matrix3d bad = Eigen::Vector3d(1e-3, 1e-3, 3e-3).asDiagonal();
  EXPECT_LT((consistent_inertia(bad) - textbook(bad)).norm(), 1e-15);
  EXPECT_GT((consistent_inertia(bad) - bad).norm(), 1e-4);
}

}  // namespace
}  // namespace massid

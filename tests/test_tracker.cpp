// The payload and offset tracker (tracker.hpp) on simulated logs of the
// UR-like arm: the wrench comes from the project's simulator
// (simulate_wrenches, dynamic) for the arm's own URDF and for a copy of it
// with an extra fixed link holding the object, so the truth never goes
// through the tracker's regressor code; the drifting offsets, the contact
// (a world-fixed force at the tool's tip) and the noise are added here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
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
#include "massid/live/tracker.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

const double kRate = 500.0, kDuration = 40.0;
const double kGrasp = 10.0, kRelease = 24.0;            // at rest
const double kContactStart = 16.0, kContactEnd = 18.0;  // in motion
const double kObjectMass = 0.8;
const Eigen::Vector3d kObjectCom(0.02, -0.01, 0.08);           // tool frame
const Eigen::Vector3d kObjectInertia(2.0e-3, 1.5e-3, 1.0e-3);  // principal, about the com
const Eigen::Vector3d kContactForce(6.0, 3.0, -7.0);           // world, N (9.7 N)
const Eigen::Vector3d kContactPoint(0.0, 0.0, 0.15);           // tool frame

// Motion windows: the arm rests outside them.
struct TrackerSegment {
  double a, b;
};
const TrackerSegment kMotion[] = {{3.0, 9.0}, {12.0, 22.0}, {26.0, 34.0}};

std::string object_urdf(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string xml = ss.str();
  const std::string object = fmt::format(
      R"(<joint name="object_joint" type="fixed"><parent link="tool"/><child link="object"/>
      <origin xyz="0 0 0" rpy="0 0 0"/></joint>
      <link name="object"><inertial><origin xyz="{} {} {}" rpy="0 0 0"/><mass value="{}"/>
      <inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{}"/></inertial></link>
      </robot>)",
      kObjectCom.x(), kObjectCom.y(), kObjectCom.z(), kObjectMass, kObjectInertia.x(),
      kObjectInertia.y(), kObjectInertia.z());
  xml.replace(xml.rfind("</robot>"), 8, object);
  return xml;
}

// The arm's joints: q0 plus a smooth envelope (zero at rest) times sines.
struct TrackerMotion {
  Eigen::VectorXd q0;
  Eigen::MatrixXd amp, freq, phase;  // [6 x 3]
  void at(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) const {
    double w = 0, w1 = 0, w2 = 0;
    const double r = 0.3;
    for (const TrackerSegment& s : kMotion) {
      if (t < s.a || t > s.b) continue;
      const double u = std::min(t - s.a, s.b - t), sign = t - s.a < s.b - t ? 1.0 : -1.0;
      if (u >= r) {
        w = 1;
      } else {
        const double k = M_PI / r;
        w = std::pow(std::sin(0.5 * k * u), 2);
        w1 = sign * 0.5 * k * std::sin(k * u);
        w2 = 0.5 * k * k * std::cos(k * u);
      }
    }
    q = q0;
    qd.setZero(6);
    qdd.setZero(6);
    for (int j = 0; j < 6; ++j)
      for (int h = 0; h < amp.cols(); ++h) {
        const double f = freq(j, h), x = f * t + phase(j, h), A = amp(j, h);
        const double g = A * std::sin(x), g1 = A * f * std::cos(x), g2 = -A * f * f * std::sin(x);
        q[j] += w * g;
        qd[j] += w1 * g + w * g1;
        qdd[j] += w2 * g + 2 * w1 * g1 + w * g2;
      }
  }
};

TrackerMotion tracker_motion(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  TrackerMotion m;
  m.q0.resize(6);
  m.q0 << 0.3, -1.3, 1.4, -1.2, -1.4, 0.4;
  m.amp.resize(6, 3);
  m.freq.resize(6, 3);
  m.phase.resize(6, 3);
  for (int j = 0; j < 6; ++j)
    for (int h = 0; h < 3; ++h) {
      m.amp(j, h) = (j < 3 ? 0.15 : 0.45) * (0.5 + U(rng)) / (h + 1);
      m.freq(j, h) = 1.5 + 2.5 * U(rng) + h;
      m.phase(j, h) = 2 * M_PI * U(rng);
    }
  return m;
}

bool tracker_in_contact(double t) { return t >= kContactStart && t < kContactEnd; }
double tracker_contact_scale(double t) {  // 50 ms ramps
  if (!tracker_in_contact(t)) return 0.0;
  return std::min({1.0, (t - kContactStart) / 0.05, (kContactEnd - t) / 0.05});
}
bool tracker_holding(double t) { return t >= kGrasp && t < kRelease; }
Wrench tracker_offset(double t) {
  Wrench o0, rate;
  o0 << 1.0, -0.5, 2.0, 0.05, -0.03, 0.02;
  rate << 0.3, -0.3, 0.3, 0.01, -0.01, 0.01;
  return o0 + rate * (t / kDuration);
}

// One tracked log: the inputs per row and the true payload.
struct TrackerLog {
  Model plain;        // what the tracker is given
  Samples samples;    // joints, gravity, sensor motion, wrench (measured)
  bool wrist = true;  // the sensor on wrist_3_link (else the base)
};

TrackerLog tracker_log(bool wrist, std::uint64_t seed) {
  const std::string urdf = test::examples()[1].urdf;  // ur_like
  const std::string sensor = wrist ? "wrist_3_link" : "";
  TrackerLog log;
  log.wrist = wrist;
  log.plain = load_urdf(urdf, sensor);
  const Model with = load_urdf_string(object_urdf(urdf), sensor, "ur_like+object");
  const TrackerMotion motion = tracker_motion(seed);
  const int n = static_cast<int>(kDuration * kRate);
  Samples& s = log.samples;
  s.source = "tracker";
  s.time.resize(n);
  s.line.resize(static_cast<std::size_t>(n));
  Eigen::MatrixXd q(n, 6), qd(n, 6), qdd(n, 6);
  Eigen::VectorXd a, b, c;
  for (int i = 0; i < n; ++i) {
    s.time[i] = i / kRate;
    s.line[static_cast<std::size_t>(i)] = i + 2;
    motion.at(s.time[i], a, b, c);
    q.row(i) = a;
    qd.row(i) = b;
    qdd.row(i) = c;
  }
  if (wrist) {
    s.q.resize(n, 0);
    s.qd.resize(n, 0);
    s.qdd.resize(n, 0);
    s.q_upstream = q;
    s.qd_upstream = qd;
    s.qdd_upstream = qdd;
    s.gravity.resize(n, 3);
    s.gravity_from_upstream = true;
    resolve_upstream(log.plain, s);
  } else {
    s.q = q;
    s.qd = qd;
    s.qdd = qdd;
    s.gravity = test::kLevel.transpose().replicate(n, 1);
  }
  SimulateOptions so;
  so.dynamic = true;
  const Eigen::MatrixXd w0 = simulate_wrenches(log.plain, s, so);
  const Eigen::MatrixXd w1 = simulate_wrenches(with, s, so);
  std::mt19937_64 rng(seed * 7919 + 1);
  std::normal_distribution<double> N(0.0, 1.0);
  KinematicsData kin(log.plain);
  const int tool = log.plain.find_link("tool");
  s.wrench.resize(n, 6);
  for (int i = 0; i < n; ++i) {
    const double t = s.time[i];
    Wrench w = (tracker_holding(t) ? w1 : w0).row(i).transpose();
    w += tracker_offset(t);
    for (int k = 0; k < 6; ++k) w[k] += N(rng) * (k < 3 ? 0.05 : 0.003);
    if (tracker_in_contact(t)) {
      // The sensor frame's orientation in the world, the tip's position in it.
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      if (wrist)
        R = upstream_kinematics(log.plain, q.row(i).transpose(), Eigen::VectorXd(),
                                Eigen::VectorXd())
                .rotation;
      forward_kinematics(log.plain, kin, s.q.row(i).transpose());
      const Eigen::Vector3d p = kin.position[tool] + kin.rotation[tool] * kContactPoint;
      const Eigen::Vector3d F = tracker_contact_scale(t) * (R.transpose() * kContactForce);
      w.head<3>() += F;
      w.tail<3>() += p.cross(F);
    }
    s.wrench.row(i) = w.transpose();
  }
  return log;
}

// The identified model: the arm's true dynamic base parameters, no offsets.
IdentifiedModel tracker_identified(const TrackerLog& log) {
  const BaseParameters base =
      find_base_parameters(log.plain, motion_base_options(log.samples, false));
  Eigen::VectorXd values = base.K * ParameterLayout::full().nominal(log.plain);
  return IdentifiedModel::from_values(log.plain, base, values);
}

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
    run.rows.push_back(tracker.update(s.time[i], q.data(), qd.data(), qdd.data(),
                                      s.gravity.row(i).transpose(), sensor,
                                      s.wrench.row(i).transpose()));
  }
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
    if (t >= 5.0) {
      const Wrench d = e.offset - tracker_offset(t);
      worst_f = std::max(worst_f, d.head<3>().cwiseAbs().maxCoeff());
      worst_m = std::max(worst_m, d.tail<3>().cwiseAbs().maxCoeff());
    }
  }
  std::cout << fmt::format(
      "tracker: {} changes; worst mass error {:.3g} %, after release {:.3g} %, com {:.3g} mm, "
      "offsets {:.3g} N {:.3g} N m; contact rows flagged {}/{}, free rows {}/{}\n",
      changes, 100 * worst_mass, 100 * worst_zero, 1e3 * worst_com, worst_f, worst_m,
      contact_flagged, contact_rows, free_flagged, free_rows);
  EXPECT_EQ(changes, 2);
  EXPECT_LT(worst_mass, 0.01);
  EXPECT_LT(worst_zero, 0.01);
  EXPECT_LT(worst_com, 0.002);
  EXPECT_LT(worst_f, 0.08);
  EXPECT_LT(worst_m, 0.004);
  EXPECT_GE(contact_flagged, 0.9 * contact_rows);
  EXPECT_LE(free_flagged, 0.01 * free_rows);
}

TEST(Tracker, WristSensorTracksGraspDriftContactAndRelease) {
  const TrackerLog log = tracker_log(true, 1);
  expect_tracked(log, track(log));
}

TEST(Tracker, BaseSensorTracksGraspDriftContactAndRelease) {
  const TrackerLog log = tracker_log(false, 2);
  expect_tracked(log, track(log));
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

}  // namespace
}  // namespace massid

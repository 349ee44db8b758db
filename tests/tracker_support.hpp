// Simulated logs for the tracker's tests (test_tracker.cpp,
// test_cli_tracker.cpp): the UR-like arm, a wrist or a base sensor, an object
// grasped at rest and put down, drifting offsets and a contact. The wrench
// comes from the project's simulator (simulate_wrenches, dynamic) for the
// arm's own URDF and for a copy of it with an extra fixed link holding the
// object, so the truth never goes through the tracker's regressor code; the
// drifting offsets, the contact (a world-fixed force at the tool's tip) and
// the noise are added here.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"
#include "test_support.hpp"

namespace massid::tracker_test {

inline const double kRate = 500.0, kDuration = 40.0;
inline const double kGrasp = 10.0, kRelease = 24.0;            // at rest
inline const double kContactStart = 16.0, kContactEnd = 18.0;  // in motion
inline const double kObjectMass = 0.8;
inline const Eigen::Vector3d kObjectCom(0.02, -0.01, 0.08);           // tool frame
inline const Eigen::Vector3d kObjectInertia(2.0e-3, 1.5e-3, 1.0e-3);  // principal, about the com
inline const Eigen::Vector3d kContactForce(6.0, 3.0, -7.0);           // world, N (9.7 N)
inline const Eigen::Vector3d kContactPoint(0.0, 0.0, 0.15);           // tool frame

// Motion windows: the arm rests outside them.
struct TrackerSegment {
  double a, b;
};
inline const TrackerSegment kMotion[] = {{3.0, 9.0}, {12.0, 22.0}, {26.0, 34.0}};

inline std::string object_urdf(const std::string& path) {
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

inline TrackerMotion tracker_motion(std::uint64_t seed) {
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

inline bool tracker_in_contact(double t) { return t >= kContactStart && t < kContactEnd; }
inline double tracker_contact_scale(double t) {  // 50 ms ramps
  if (!tracker_in_contact(t)) return 0.0;
  return std::min({1.0, (t - kContactStart) / 0.05, (kContactEnd - t) / 0.05});
}
inline bool tracker_holding(double t) { return t >= kGrasp && t < kRelease; }
inline Wrench tracker_offset(double t) {
  Wrench o0, rate;
  o0 << 1.0, -0.5, 2.0, 0.05, -0.03, 0.02;
  rate << 0.3, -0.3, 0.3, 0.01, -0.01, 0.01;
  return o0 + rate * (t / kDuration);
}

// One tracked log: the inputs per row and the true payload.
struct TrackerLog {
  Model plain;            // what the tracker is given
  Samples samples;        // joints, gravity, sensor motion, wrench (measured)
  bool wrist = true;      // the sensor on wrist_3_link (else the base)
  Eigen::MatrixXd noise;  // [rows x 6] the noise added to the wrench (N, N m)
};

// The contact's wrench on the sensor at row i of a log (zero outside the
// contact): the world-fixed force at the tool's tip, in the sensor frame.
inline Wrench tracker_contact_wrench(const TrackerLog& log, int i) {
  const Samples& s = log.samples;
  const double t = s.time[i];
  if (!tracker_in_contact(t)) return Wrench::Zero();
  // The sensor frame's orientation in the world, the tip's position in it.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (log.wrist)
    R = upstream_kinematics(log.plain, s.q_upstream.row(i).transpose(), Eigen::VectorXd(),
                            Eigen::VectorXd())
            .rotation;
  KinematicsData kin(log.plain);
  forward_kinematics(log.plain, kin, s.q.row(i).transpose());
  const int tool = log.plain.find_link("tool");
  const Eigen::Vector3d p = kin.position[tool] + kin.rotation[tool] * kContactPoint;
  const Eigen::Vector3d F = tracker_contact_scale(t) * (R.transpose() * kContactForce);
  Wrench w;
  w << F, p.cross(F);
  return w;
}

inline TrackerLog tracker_log(bool wrist, std::uint64_t seed, bool events = true) {
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
  s.wrench.resize(n, 6);
  log.noise.resize(n, 6);
  for (int i = 0; i < n; ++i) {
    const double t = s.time[i];
    Wrench w = (events && tracker_holding(t) ? w1 : w0).row(i).transpose();
    if (events) w += tracker_offset(t);
    for (int k = 0; k < 6; ++k) log.noise(i, k) = N(rng) * (k < 3 ? 0.05 : 0.003);
    w += log.noise.row(i).transpose();
    if (events) w += tracker_contact_wrench(log, i);
    s.wrench.row(i) = w.transpose();
  }
  return log;
}

// The identified model: the arm's true dynamic base parameters, no offsets.
inline IdentifiedModel tracker_identified(const TrackerLog& log) {
  const BaseParameters base =
      find_base_parameters(log.plain, motion_base_options(log.samples, false));
  Eigen::VectorXd values = base.K * ParameterLayout::full().nominal(log.plain);
  return IdentifiedModel::from_values(log.plain, base, values);
}

// The log as a CSV for `massid compensate`: t, the arm's joints (JOINT,
// JOINT_vel, JOINT_acc) and fx..mz.
inline std::string tracker_csv(const TrackerLog& log, const Model& arm) {
  const Samples& s = log.samples;
  const bool wrist = log.wrist;
  std::string out = "t";
  for (const Joint& j : arm.joints) out += "," + j.name;
  for (const Joint& j : arm.joints) out += "," + j.name + "_vel";
  for (const Joint& j : arm.joints) out += "," + j.name + "_acc";
  out += ",fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < s.size(); ++i) {
    out += fmt::format("{}", s.time[i]);
    const auto& q = wrist ? s.q_upstream : s.q;
    const auto& qd = wrist ? s.qd_upstream : s.qd;
    const auto& qdd = wrist ? s.qdd_upstream : s.qdd;
    for (const auto* m : {&q, &qd, &qdd})
      for (int j = 0; j < m->cols(); ++j) out += fmt::format(",{}", (*m)(i, j));
    for (int k = 0; k < 6; ++k) out += fmt::format(",{}", s.wrench(i, k));
    out += "\n";
  }
  return out;
}

}  // namespace massid::tracker_test

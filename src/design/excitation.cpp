#include "massid/design/excitation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "massid/io/csv.hpp"

namespace massid {

void FourierTrajectory::evaluate(double t, Eigen::Ref<Eigen::VectorXd> q,
                                 Eigen::Ref<Eigen::VectorXd> qd,
                                 Eigen::Ref<Eigen::VectorXd> qdd) const {
  const double w = 2.0 * std::numbers::pi / period;
  q = q0;
  qd.setZero();
  qdd.setZero();
  for (int k = 1; k <= harmonics(); ++k) {
    const double s = std::sin(k * w * t), c = std::cos(k * w * t), kw = k * w;
    for (int j = 0; j < num_joints(); ++j) {
      const double aj = a(j, k - 1), bj = b(j, k - 1);
      q[j] += (aj * s - bj * c) / kw;
      qd[j] += aj * c + bj * s;
      qdd[j] += kw * (bj * c - aj * s);
    }
  }
}

std::vector<Joint> trajectory_joints(const Model& model) {
  std::vector<Joint> out = model.upstream_joints;
  out.insert(out.end(), model.joints.begin(), model.joints.end());
  return out;
}

FourierTrajectory random_fourier_trajectory(const Model& model, int harmonics, double period,
                                            std::uint64_t seed, const ExcitationLimits& limits) {
  return random_fourier_trajectory(model.joints, harmonics, period, seed, limits);
}

FourierTrajectory random_fourier_trajectory(const std::vector<Joint>& joints, int harmonics,
                                            double period, std::uint64_t seed,
                                            const ExcitationLimits& limits) {
  const int nj = static_cast<int>(joints.size()), K = std::max(1, harmonics);
  FourierTrajectory tr;
  tr.period = period;
  tr.q0.resize(nj);
  tr.a.resize(nj, K);
  tr.b.resize(nj, K);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  for (int j = 0; j < nj; ++j) {
    const Joint& joint = joints[j];
    tr.q0[j] = joint.limited ? 0.5 * (joint.lower + joint.upper) : 0.0;
    for (int k = 0; k < K; ++k) {
      tr.a(j, k) = normal(rng) / (k + 1);
      tr.b(j, k) = normal(rng) / (k + 1);
    }
    // At rest at t = 0: sum_k a_k = 0 and sum_k k b_k = 0 (harmonic 1 absorbs them).
    if (K > 1) {
      tr.a(j, 0) -= tr.a.row(j).sum();
      double kb = 0.0;
      for (int k = 1; k < K; ++k) kb += (k + 1) * tr.b(j, k);
      tr.b(j, 0) = -kb;
    } else {
      tr.a(j, 0) = 0.0;  // one harmonic: velocity zero at t = 0 (acceleration not)
    }
  }
  // Scale each joint to its tightest limit, judged on a dense grid over one period.
  const int grid = 400 * K;
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  Eigen::VectorXd dev = Eigen::VectorXd::Zero(nj), vel = dev, acc = dev;
  for (int i = 0; i < grid; ++i) {
    tr.evaluate(period * i / grid, q, qd, qdd);
    dev = dev.cwiseMax((q - tr.q0).cwiseAbs());
    vel = vel.cwiseMax(qd.cwiseAbs());
    acc = acc.cwiseMax(qdd.cwiseAbs());
  }
  for (int j = 0; j < nj; ++j) {
    const Joint& joint = joints[j];
    const double amplitude =
        joint.limited ? 0.5 * (joint.upper - joint.lower) * (1.0 - 2.0 * limits.position_margin)
                      : limits.unlimited_amplitude;
    const double vmax = joint.velocity_limit > 0 ? joint.velocity_limit : limits.default_velocity;
    double scale = amplitude / std::max(dev[j], 1e-300);
    scale = std::min(scale, vmax / std::max(vel[j], 1e-300));
    const double amax =
        j < static_cast<int>(limits.joint_acceleration.size()) && limits.joint_acceleration[j] > 0
            ? limits.joint_acceleration[j]
            : limits.acceleration;
    scale = std::min(scale, amax / std::max(acc[j], 1e-300));
    tr.a.row(j) *= scale;
    tr.b.row(j) *= scale;
  }
  return tr;
}

Samples sample_trajectory(const FourierTrajectory& tr, double duration, double rate,
                          const Eigen::Vector3d& gravity) {
  const int nj = tr.num_joints();
  const int N = static_cast<int>(std::floor(duration * rate + 1e-9)) + 1;
  Samples s;
  s.source = "trajectory";
  s.q.resize(N, nj);
  s.qd.resize(N, nj);
  s.qdd.resize(N, nj);
  s.gravity.resize(N, 3);
  s.time.resize(N);
  s.line.resize(N);
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  for (int i = 0; i < N; ++i) {
    const double t = i / rate;
    tr.evaluate(t, q, qd, qdd);
    s.q.row(i) = q.transpose();
    s.qd.row(i) = qd.transpose();
    s.qdd.row(i) = qdd.transpose();
    s.gravity.row(i) = gravity.transpose();
    s.time[i] = t;
    s.line[i] = i + 1;
  }
  return s;
}

void write_trajectory(const std::string& path, const Model& model, const Samples& s) {
  const bool wrist = s.q_upstream.cols() > 0;
  std::vector<std::string> names;
  for (const Joint& j : trajectory_joints(model))
    if (wrist || j.link >= 0) names.push_back(j.name);
  for (const auto& held : model.held) names.push_back(held.first);
  std::vector<std::string> header{"t"};
  for (const char* suffix : {"", "_vel", "_acc"})
    for (const std::string& n : names) header.push_back(n + suffix);
  if (!wrist)
    for (const char* g : {"gx", "gy", "gz"}) header.push_back(g);
  const bool blocks = s.block.size() == static_cast<size_t>(s.size());
  if (blocks) header.push_back("block");
  std::vector<std::vector<std::string>> rows(s.size());
  for (int i = 0; i < s.size(); ++i) {
    auto& r = rows[i];
    r.push_back(format_number(s.time[i]));
    const auto put = [&](const Eigen::MatrixXd& upstream, const Eigen::MatrixXd& own,
                         bool position) {
      if (wrist)
        for (Eigen::Index c = 0; c < upstream.cols(); ++c)
          r.push_back(format_number(upstream(i, c)));
      for (Eigen::Index c = 0; c < own.cols(); ++c) r.push_back(format_number(own(i, c)));
      for (const auto& held : model.held) r.push_back(format_number(position ? held.second : 0.0));
    };
    put(s.q_upstream, s.q, true);
    put(s.qd_upstream, s.qd, false);
    put(s.qdd_upstream, s.qdd, false);
    if (!wrist)
      for (Eigen::Index c = 0; c < 3; ++c) r.push_back(format_number(s.gravity(i, c)));
    if (blocks) r.push_back(std::to_string(s.block[i]));
  }
  write_csv(path, header, rows);
}

}  // namespace massid

#include "massid/design/excitation.hpp"

#include <cmath>
#include <numbers>
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

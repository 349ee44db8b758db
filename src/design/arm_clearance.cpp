#include "design/arm_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace massid {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Distance between segments [p0, p1] and [q0, q1].
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  // Closest points of two segments (Ericson, Real-Time Collision Detection 5.1.9).
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double eps = 1e-18;
  double s = 0.0, t = 0.0;
  if (a <= eps && e <= eps) return r.norm();
  if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > eps ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

}  // namespace

ArmClearance::ArmClearance(const Model& model, const Eigen::Vector3d& root_gravity)
    : model_(model), up_(-root_gravity.normalized()), kin_(model) {
  int body = 0;
  bool moves = false;
  body_name_.push_back(model.root_link);
  for (const ChainStep& step : model.upstream) {
    if (step.joint_index >= 0) {
      ++body;
      moves = true;
      body_name_.push_back("the link moved by '" + step.joint + "'");
    }
    body_of_step_.push_back(body);
    step_moves_.push_back(moves);
  }
  tool_body_ = body;
  // Only the origins whose height changes count (the shoulder's turns at
  // the height the mount gives it).
  const std::vector<bool> varies =
      heights_vary(model.upstream_joints, model.upstream.size(),
                   [&](const Eigen::VectorXd& qu, std::vector<double>& h) {
                     upstream_link_poses(model, qu, poses_);
                     for (size_t k = 0; k < poses_.size(); ++k)
                       h[k] = up_.dot(poses_[k].translation());
                   });
  for (size_t k = 0; k < varies.size(); ++k) step_moves_[k] = step_moves_[k] && varies[k];
  tool_ = clearance_points(model);
}

std::vector<ClearancePoint> clearance_points(const Model& model) {
  std::vector<ClearancePoint> out;
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    out.push_back({l, Eigen::Vector3d::Zero(), 0.0});
    if (link.mass > 0.0) out.push_back({l, link.com, 0.0});
    for (const Link::Sphere& s : link.collision) out.push_back({l, s.centre, s.radius});
  }
  return out;
}

ArmClearanceValue ArmClearance::at(const Eigen::Ref<const Eigen::VectorXd>& qu,
                                   const Eigen::Ref<const Eigen::VectorXd>& q) {
  upstream_link_poses(model_, qu, poses_);
  forward_kinematics(model_, kin_, q);
  ArmClearanceValue out{kInf, "", kInf, ""};
  // Segments of every body: (body, a, b, link name at b).
  struct Segment {
    int body;
    Eigen::Vector3d a, b;
    const std::string* link;
  };
  std::vector<Segment> segments;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  int previous_body = 0;
  for (size_t k = 0; k < poses_.size(); ++k) {
    const Eigen::Vector3d p = poses_[k].translation();
    if (step_moves_[k]) {
      const double h = up_.dot(p);
      if (h < out.height) {
        out.height = h;
        out.low_link = body_name_[body_of_step_[k]];
      }
    }
    // The segment to this origin belongs to the body the step leaves: the
    // joint's origin is fixed in its parent.
    segments.push_back({previous_body, previous, p, &body_name_[previous_body]});
    previous = p;
    previous_body = body_of_step_[k];
  }
  const Eigen::Isometry3d& sensor = poses_.empty() ? Eigen::Isometry3d::Identity() : poses_.back();
  for (const ClearancePoint& t : tool_) {
    const Eigen::Vector3d p = sensor * (kin_.position[t.link] + kin_.rotation[t.link] * t.p);
    const double h = up_.dot(p) - t.radius;
    if (h < out.height) {
      out.height = h;
      out.low_link = model_.links[t.link].name;
    }
    segments.push_back({tool_body_, sensor.translation(), p, &model_.links[t.link].name});
  }
  for (size_t i = 0; i < segments.size(); ++i)
    for (size_t j = i + 1; j < segments.size(); ++j) {
      if (std::abs(segments[i].body - segments[j].body) < 2) continue;
      const double d = segment_distance(segments[i].a, segments[i].b, segments[j].a, segments[j].b);
      if (d < out.self) {
        out.self = d;
        out.self_pair = *segments[i].link + " / " + *segments[j].link;
      }
    }
  return out;
}

}  // namespace massid

#include "design/design_space.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "massid/core/errors.hpp"

namespace massid {

// Joint j's range: its limits less `margin` of the range at each end (a
// generic range when unlimited), narrowed by the user's `limits`; empty(lo,
// hi) throws with the range given when that leaves nothing.
template <class Empty>
DesignSpace::Free DesignSpace::narrowed(int j, const Joint& joint, double margin,
                                        const DesignOptions& o, Empty empty) {
  Free f{j, joint.generic_position(0.0), joint.generic_position(1.0)};
  if (joint.limited) {
    const double m = margin * (joint.upper - joint.lower);
    f.lo = joint.lower + m;
    f.hi = joint.upper - m;
  }
  if (auto l = o.limits.find(joint.name); l != o.limits.end()) {
    f.lo = std::max(f.lo, l->second.first);
    f.hi = std::min(f.hi, l->second.second);
    if (!(f.hi > f.lo)) empty(l->second.first, l->second.second);
  }
  return f;
}

DesignSpace::DesignSpace(const Model& model, const DesignOptions& o)
    : model_(model), level_(o.level_gravity), min_height_(o.min_height), kin_(model) {
  if (!(level_.norm() > 0.0))
    throw InputError("design: the level gravity vector is zero",
                     {{Hint::Setting::LevelGravity, ""}});
  for (const auto& limit : o.limits) {
    const std::string& name =
        limit.first;  // (a lambda cannot capture a structured binding in C++17)
    if (model.find_joint(name) < 0 &&
        std::none_of(model.upstream_joints.begin(), model.upstream_joints.end(),
                     [&](const Joint& j) { return j.name == name; }))
      throw InputError(
          fmt::format("design: joint range for '{}', which is not a movable joint below the "
                      "sensor link",
                      name),
          {{Hint::Setting::Limits, name + "=LO:HI"}});
  }
  for (int j = 0; j < model.num_joints(); ++j) {
    const Joint& joint = model.joints[j];
    free_.push_back(narrowed(j, joint, o.position_margin, o, [&](double lo, double hi) {
      throw InputError(
          fmt::format("design: the range {}:{} of joint '{}' is empty within the URDF limits "
                      "[{}, {}] less the margin of {:g} % of the range at each end ([{:.6g}, "
                      "{:.6g}])",
                      lo, hi, joint.name, joint.lower, joint.upper, 100 * o.position_margin,
                      joint.lower + o.position_margin * (joint.upper - joint.lower),
                      joint.upper - o.position_margin * (joint.upper - joint.lower)),
          {{Hint::Setting::Limits, fmt::format("{}={}:{}", joint.name, lo, hi)}});
    }));
  }
  if (o.tilt_max) {
    cone_ = true;
    tilt_max_ = *o.tilt_max;
    groups_ = std::max(0, o.tilt_groups);
    if (!(tilt_max_ >= 0.0 && tilt_max_ < std::numbers::pi / 2))
      throw InputError("design: the largest tilt must be between 0 and 90 degrees",
                       {{Hint::Setting::TiltMax, ""}});
    tilts_ = cone_tilts(level_, tilt_max_, groups_);  // tilt groups start on the rim
  } else {
    tilts_ = o.tilts.empty() ? std::vector<Tilt>{Tilt{}} : o.tilts;
  }
  const auto level = std::find_if(tilts_.begin(), tilts_.end(),
                                  [&](const Tilt& t) { return tilt_angle(level_, t) < 1e-12; });
  if (!cone_ && level != tilts_.end()) level_group_ = static_cast<int>(level - tilts_.begin());
  // The points checked for clearance, those whose height changes: one that
  // moves at a constant height (a centre of mass off a vertical axis) is
  // where the mount puts it, as the fixed links are.
  const std::vector<ClearancePoint> all = clearance_points(model);
  const Eigen::Vector3d up = -level_.normalized();
  const std::vector<bool> moves =
      heights_vary(model.joints, all.size(), [&](const Eigen::VectorXd& q, std::vector<double>& h) {
        forward_kinematics(model, kin_, q);
        for (size_t i = 0; i < all.size(); ++i)
          h[i] = up.dot(kin_.position[all[i].link] + kin_.rotation[all[i].link] * all[i].p);
      });
  for (size_t i = 0; i < all.size(); ++i)
    if (moves[i]) points_.push_back(all[i]);
  if (model.num_upstream_joints() > 0 && o.move_arm) init_arm(o);
}

bool DesignSpace::level_allowed() const { return cone_ || level_group_ >= 0; }

bool DesignSpace::tilts_other_than_level() const {
  return cone_ ? tilt_max_ > 0.0 : std::any_of(tilts_.begin(), tilts_.end(), [&](const Tilt& t) {
    return tilt_angle(level_, t) >= 1e-12;
  });
}

double DesignSpace::clearance(const Eigen::VectorXd& q, int* link) {
  forward_kinematics(model_, kin_, q);
  const Eigen::Vector3d up = -level_.normalized();
  double lowest = std::numeric_limits<double>::infinity();
  for (const ClearancePoint& pt : points_) {
    const double h = up.dot(kin_.position[pt.link] + kin_.rotation[pt.link] * pt.p) - pt.radius;
    if (h < lowest) {
      lowest = h;
      if (link) *link = pt.link;
    }
  }
  return lowest;
}

void DesignSpace::relax_min_height_if_infeasible(bool required) {
  if (!min_height_ || required || points_.empty() || arm_) return;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd q(model_.num_joints());
  for (int attempt = 0; attempt < 2000; ++attempt) {
    for (const Free& f : free_) q[f.joint] = f.lo + (f.hi - f.lo) * u(rng);
    if (clearance(q) >= *min_height_) return;
  }
  min_height_.reset();
  relaxed_ = true;
}

bool DesignSpace::high_enough(const PlanPose& pose) {
  if (arm_) {
    const ArmClearanceValue v = arm_->at(pose.q_upstream, pose.q);
    return (!min_height_ || v.height >= *min_height_) &&
           (!self_clearance_ || v.self >= *self_clearance_);
  }
  return !min_height_ || clearance(pose.q) >= *min_height_;
}

namespace {

// The tilt scaled back onto the cone of half-angle tilt_max when outside it.
Tilt clamp_to_cone(const Eigen::Vector3d& level, double tilt_max, Tilt t) {
  if (tilt_angle(level, t) <= tilt_max) return t;
  double lo = 0.0, hi = 1.0;  // scale the tilt back onto the cone
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (tilt_angle(level, {mid * t.x, mid * t.y}) <= tilt_max ? lo : hi) = mid;
  }
  return {lo * t.x, lo * t.y};
}

}  // namespace

std::vector<Tilt> cone_tilts(const Eigen::Vector3d& level, double tilt_max, int count) {
  std::vector<Tilt> out;
  for (int k = 0; k < count; ++k) {
    const double az = 2 * std::numbers::pi * (k + 0.25) / count;
    out.push_back(clamp_to_cone(level, tilt_max,
                                {1.5 * tilt_max * std::cos(az), 1.5 * tilt_max * std::sin(az)}));
  }
  return out;
}

PlanPose DesignSpace::sample(std::mt19937_64& rng, bool level) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PlanPose pose;
  pose.q.resize(model_.num_joints());
  if (arm_) pose.q_upstream.resize(model_.num_upstream_joints());
  for (int attempt = 0; attempt < 10000; ++attempt) {
    for (const Free& f : free_) position(pose, f) = f.lo + (f.hi - f.lo) * u(rng);
    if (!high_enough(pose)) continue;
    pose.level = level;
    if (level) {
      pose.tilt = Tilt{};
      pose.group = cone_ ? -1 : level_group_;
    } else if (own_tilt()) {
      // Half on the cone's rim (where good plans go: overshoot, then clamp), half inside.
      const double az = 2 * std::numbers::pi * u(rng);
      const double angle = u(rng) < 0.5 ? 1.5 * tilt_max_ : tilt_max_ * std::sqrt(u(rng));
      pose.tilt = clamp_to_cone(level_, tilt_max_, {angle * std::cos(az), angle * std::sin(az)});
    } else {
      pose.group = std::min<int>(num_tilts() - 1, static_cast<int>(u(rng) * num_tilts()));
      pose.tilt = tilts_[pose.group];
    }
    pose.gravity = tilted_gravity(level_, pose.tilt);
    arm_pose(pose);
    return pose;
  }
  throw InputError(
      fmt::format(
          "design: no pose satisfies the constraints (a clearance of {} m above the platform plane "
          "with the joint ranges given): lower it, or turn it off to allow links below the plane",
          min_height_.value_or(0.0)),
      {{Hint::Setting::MinHeight, "lower"}, {Hint::Setting::MinHeight, "none"}});
}

Eigen::VectorXd DesignSpace::coordinates(const PlanPose& pose) const {
  Eigen::VectorXd x(dimension());
  for (size_t i = 0; i < free_.size(); ++i) x[i] = position(pose, free_[i]);
  if (own_tilt()) x.tail<2>() << pose.tilt.x, pose.tilt.y;
  return x;
}

bool DesignSpace::pose_at(const Eigen::VectorXd& x, const PlanPose& like, PlanPose& out) {
  out.q.resize(model_.num_joints());
  if (arm_) out.q_upstream.resize(model_.num_upstream_joints());
  for (size_t i = 0; i < free_.size(); ++i)
    position(out, free_[i]) = std::clamp(x[i], free_[i].lo, free_[i].hi);
  out.group = like.group;
  out.level = like.level;
  out.tilt = own_tilt() && !like.level
                 ? clamp_to_cone(level_, tilt_max_, {x[dimension() - 2], x[dimension() - 1]})
                 : like.tilt;
  out.gravity = tilted_gravity(level_, out.tilt);
  arm_pose(out);
  return high_enough(out);
}

Eigen::VectorXd DesignSpace::steps() const {
  Eigen::VectorXd s(dimension());
  for (size_t i = 0; i < free_.size(); ++i) s[i] = 0.25 * (free_[i].hi - free_[i].lo);
  if (own_tilt()) s.tail<2>().setConstant(0.5 * tilt_max_);
  return s;
}

Tilt DesignSpace::set_tilt(int k, Tilt t) {
  return tilts_[k] = clamp_to_cone(level_, tilt_max_, t);
}

double DesignSpace::clearance(const PlanPose& pose, std::string* what) {
  if (arm_) {
    const ArmClearanceValue v = arm_->at(pose.q_upstream, pose.q);
    if (what) *what = v.low_link;
    return v.height;
  }
  int link = -1;
  const double h = clearance(pose.q, &link);
  if (what) *what = link >= 0 ? model_.links[link].name : "";
  return h;
}

// A wrist: the poses move the arm's joints within their limits less 10 % of
// the range at each end (as design --dynamic), narrowed by `limits`; gravity
// in the sensor frame follows from them and the root gravity; the clearances
// are the arm's (arm_clearance.hpp).
void DesignSpace::init_arm(const DesignOptions& o) {
  if (o.tilt_max || !o.tilts.empty())
    throw InputError(
        fmt::format("design: sensor link '{}' is below movable joints (a wrist): gravity in its "
                    "frame follows from the arm's joints and --root-gravity, not platform tilts",
                    model_.sensor_link()));
  constexpr double kArmMargin = 0.1;
  for (int j = 0; j < model_.num_upstream_joints(); ++j) {
    const Joint& joint = model_.upstream_joints[j];
    free_.push_back(narrowed(j, joint, kArmMargin, o, [&](double lo, double hi) {
      throw InputError(fmt::format("design: the range {}:{} of joint '{}' is empty within its "
                                   "limits less 10 %",
                                   lo, hi, joint.name),
                       {{Hint::Setting::Limits, joint.name + "=LO:HI"}});
    }));
    free_.back().arm = true;
  }
  root_gravity_ = o.root_gravity;
  self_clearance_ = o.self_clearance;
  arm_.emplace(model_, o.root_gravity);
}

void DesignSpace::arm_pose(PlanPose& pose) const {
  if (!arm_) return;
  upstream_sensor_frame(model_, pose.q_upstream.data(), nullptr, nullptr, root_gravity_,
                        pose.gravity.data(), nullptr);
}

}  // namespace massid

#include "massid/design/design.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "design/design_criterion.hpp"
#include "design/design_space.hpp"
#include "design/plan_order.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identifiability.hpp"

namespace massid {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A plan under optimisation: poses, their criterion rows, the information matrix.
struct Working {
  std::vector<PlanPose> poses;
  std::vector<Eigen::MatrixXd> rows;
  Eigen::MatrixXd info;
  double value = kInfinity;
};

// Greedy D-optimal start on the criterion rows (a small ridge keeps the first
// steps defined): each step adds the candidate with the largest
// log det(I + R^T R) = log det I + log det(1 + R I^-1 R^T). The first
// `level` poses come from the level candidates (level[c]), the rest from the others.
Working greedy_start(const std::vector<PlanPose>& cand,
                     const std::vector<Eigen::MatrixXd>& cand_rows, int poses, int level, int n) {
  Working w;
  double trace = 0.0;
  for (const auto& r : cand_rows) trace += r.squaredNorm();
  w.info = Eigen::MatrixXd::Identity(n, n) * (1e-8 * trace / cand_rows.size());
  const Eigen::MatrixXd ridge = w.info;
  for (int t = 0; t < poses; ++t) {
    const Eigen::MatrixXd inv = w.info.llt().solve(Eigen::MatrixXd::Identity(n, n));
    double best = -kInfinity;
    size_t pick = 0;
    for (size_t c = 0; c < cand.size(); ++c) {
      if (cand[c].level != (t < level)) continue;
      const Eigen::MatrixXd& R = cand_rows[c];
      Eigen::MatrixXd S = R * inv * R.transpose();
      S.diagonal().array() += 1.0;
      const double gain = Eigen::LLT<Eigen::MatrixXd>(S).matrixLLT().diagonal().array().log().sum();
      if (gain > best) best = gain, pick = c;
    }
    w.poses.push_back(cand[pick]);
    w.rows.push_back(cand_rows[pick]);
    w.info += cand_rows[pick].transpose() * cand_rows[pick];
  }
  w.info -= ridge;
  return w;
}

// Fedorov exchange: replace a pose by the candidate that improves the
// criterion most; sweeps until no exchange helps. Each position scans a
// random subset of the candidates (all when few).
bool exchange(Working& w, const std::vector<PlanPose>& cand,
              const std::vector<Eigen::MatrixXd>& cand_rows, const CriterionRows& crit,
              std::mt19937_64& rng) {
  const size_t scan = std::min<size_t>(cand.size(), 600);
  std::uniform_int_distribution<size_t> pick(0, cand.size() - 1);
  bool any = false;
  for (int sweep = 0; sweep < 6; ++sweep) {
    bool improved = false;
    for (size_t i = 0; i < w.poses.size(); ++i) {
      const Eigen::MatrixXd without = w.info - w.rows[i].transpose() * w.rows[i];
      double best = w.value;
      size_t best_c = cand.size();
      for (size_t k = 0; k < scan; ++k) {
        const size_t c = scan == cand.size() ? k : pick(rng);
        if (cand[c].level != w.poses[i].level) continue;  // level slots stay level
        const double v = crit.value(without + cand_rows[c].transpose() * cand_rows[c]);
        if (v < best) best = v, best_c = c;
      }
      if (best_c < cand.size() && best < w.value * (1.0 - 1e-9)) {
        w.poses[i] = cand[best_c];
        w.rows[i] = cand_rows[best_c];
        w.info = without + w.rows[i].transpose() * w.rows[i];
        w.value = best;
        improved = any = true;
      }
    }
    if (!improved) break;
  }
  return any;
}

// Pattern search on each pose's continuous coordinates (free joints, cone tilt).
bool refine(Working& w, DesignSpace& space, CriterionRows& crit) {
  if (space.dimension() == 0) return false;
  bool any = false;
  Eigen::MatrixXd R(crit.num_rows(), crit.size());
  PlanPose trial;
  for (size_t i = 0; i < w.poses.size(); ++i) {
    Eigen::VectorXd x = space.coordinates(w.poses[i]);
    Eigen::VectorXd step = space.steps();
    const double stop = 1e-3 * step.maxCoeff();
    Eigen::MatrixXd without = w.info - w.rows[i].transpose() * w.rows[i];
    for (int evals = 0; evals < 400 && step.maxCoeff() > stop;) {
      bool moved = false;
      for (int d = 0; d < x.size() && !moved; ++d) {
        for (double sign : {1.0, -1.0}) {
          Eigen::VectorXd y = x;
          y[d] += sign * step[d];
          ++evals;
          if (!space.pose_at(y, w.poses[i], trial)) continue;
          crit.rows(trial.q, trial.gravity, R);
          const Eigen::MatrixXd info = without + R.transpose() * R;
          const double v = crit.value(info);
          if (v < w.value * (1.0 - 1e-12)) {
            w.poses[i] = trial;
            w.rows[i] = R;
            w.info = info;
            w.value = v;
            x = space.coordinates(trial);
            moved = any = true;
            break;
          }
        }
      }
      if (!moved) step *= 0.5;
    }
  }
  return any;
}

// Pattern search on the shared tilt groups: moving a group's tilt moves every
// pose and candidate of that group.
bool refine_tilts(Working& w, std::vector<PlanPose>& cand, std::vector<Eigen::MatrixXd>& cand_rows,
                  DesignSpace& space, CriterionRows& crit) {
  if (!space.tilts_adjustable()) return false;
  bool any = false;
  auto retilt = [&](PlanPose& p, const Tilt& t) {
    p.tilt = t;
    p.gravity = tilted_gravity(space.level(), t);
  };
  for (int k = 0; k < space.num_tilts(); ++k) {
    Tilt best = space.tilt(k);
    bool changed = false;
    for (double step = 0.5 * space.tilt_max(); step > 5e-4 * space.tilt_max();) {
      bool moved = false;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const Tilt t = space.set_tilt(k, {best.x + dx * step, best.y + dy * step});
        Working trial = w;
        for (size_t i = 0; i < trial.poses.size(); ++i) {
          if (trial.poses[i].group != k) continue;
          trial.info -= trial.rows[i].transpose() * trial.rows[i];
          retilt(trial.poses[i], t);
          crit.rows(trial.poses[i].q, trial.poses[i].gravity, trial.rows[i]);
          trial.info += trial.rows[i].transpose() * trial.rows[i];
        }
        trial.value = crit.value(trial.info);
        if (trial.value < w.value * (1.0 - 1e-12)) {
          w = std::move(trial);
          best = t;
          moved = changed = any = true;
          break;
        }
      }
      if (!moved) step *= 0.5;
    }
    space.set_tilt(k, best);
    if (!changed) continue;
    for (size_t c = 0; c < cand.size(); ++c) {
      if (cand[c].group != k) continue;
      retilt(cand[c], best);
      crit.rows(cand[c].q, cand[c].gravity, cand_rows[c]);
    }
  }
  return any;
}

Samples to_samples(const std::vector<PlanPose>& plan, int num_joints) {
  Samples s;
  s.source = "the best plan found";
  s.q.resize(plan.size(), num_joints);
  s.gravity.resize(plan.size(), 3);
  for (size_t i = 0; i < plan.size(); ++i) {
    s.q.row(i) = plan[i].q.transpose();
    s.gravity.row(i) = plan[i].gravity.transpose();
    s.line.push_back(static_cast<int>(i) + 1);
  }
  return s;
}

// The plan's lowest clearance, travel, condition number, covariance at the
// given noise and the expected error of predicted wrenches over random
// feasible poses.
void figures(const Model& model, const BaseParameters& base, const Samples& plan,
             const DesignOptions& o, DesignSpace& space, DesignSummary& out) {
  out.lowest_clearance = kInfinity;
  for (const PlanPose& p : out.plan) {
    std::string what;
    const double h = space.clearance(p, &what);
    if (h < out.lowest_clearance) {
      out.lowest_clearance = h;
      out.lowest_link = what;
    }
  }
  out.links_with_meshes = 0;
  for (const Link& l : model.links) out.links_with_meshes += l.collision_meshes > 0;
  const PlanTravel travel = plan_travel(out.plan);
  out.tilt_changes = travel.tilt_changes;
  out.joint_travel = travel.joint_travel;
  const Eigen::MatrixXd A = stacked_regressor(model, base, plan);
  out.condition_number = moment_condition_number(base, A);
  const IdentifiabilityReport id = check_identifiability(model, base, plan, A, 1e-9);
  out.identifiable = id.ok();
  out.identifiability_message = id.message;
  const int p = base.num_unknowns();
  out.predicted_std = Eigen::VectorXd::Constant(p, kInfinity);
  out.expected_error.setConstant(kInfinity);
  if (!out.identifiable) return;
  Eigen::MatrixXd Aw = A;
  for (int r = 0; r < A.rows(); ++r) Aw.row(r) /= (r % 6 < 3 ? o.noise_force : o.noise_moment);
  const Eigen::MatrixXd info = Aw.transpose() * Aw;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  out.log_det = ldlt.vectorD().array().log().sum();
  const Eigen::MatrixXd cov = ldlt.solve(Eigen::MatrixXd::Identity(p, p));
  out.predicted_std = cov.diagonal().cwiseSqrt();
  std::mt19937_64 rng(12345);
  RegressorData reg(model, base);
  const int draws = 400;
  Wrench sum = Wrench::Zero();
  for (int k = 0; k < draws; ++k) {
    const PlanPose pose = space.sample(rng);
    base_regressor(model, base, reg, pose.q, pose.gravity);
    sum += (reg.base * cov * reg.base.transpose()).diagonal();
  }
  out.expected_error = (sum / draws).cwiseSqrt();
}

}  // namespace

DesignSummary design(const Model& model, const BaseParameters& base, const DesignOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (o.poses < 1)
    throw InputError("design: the number of poses must be at least 1",
                     {{Hint::Setting::Poses, ""}});
  DesignOptions opts = o;
  {
    DesignSpace probe(model, opts);
    probe.relax_min_height_if_infeasible(o.min_height_required);
    if (probe.min_height_relaxed()) opts.min_height.reset();
  }
  DesignSpace space(model, opts);
  CriterionRows crit(model, base, opts.criterion, opts.noise_force, opts.noise_moment);
  std::mt19937_64 rng(o.seed);

  const int count =
      o.candidates > 0 ? o.candidates : std::clamp(300 * (space.dimension() + 1), 1000, 3000);
  // Level poses kept when level and other tilts are allowed (see DesignOptions).
  int level = 0;
  if (space.level_allowed() && space.tilts_other_than_level() && o.poses >= 2)
    level = o.level_poses < 0 ? std::max(1, o.poses / 4) : std::min(o.level_poses, o.poses - 1);
  std::vector<PlanPose> cand;
  std::vector<Eigen::MatrixXd> cand_rows;
  const int level_count = level > 0 ? std::max(count / 4, 200) : 0;
  for (int c = 0; c < count + level_count; ++c) {
    cand.push_back(space.sample(rng, c >= count));
    cand_rows.emplace_back(crit.num_rows(), crit.size());
    crit.rows(cand.back().q, cand.back().gravity, cand_rows.back());
  }

  Working w = greedy_start(cand, cand_rows, o.poses, level, crit.size());
  w.value = crit.value(w.info);
  for (int round = 0; round < 4; ++round) {
    const bool exchanged = exchange(w, cand, cand_rows, crit, rng);
    const bool refined = refine(w, space, crit);
    const bool retilted = refine_tilts(w, cand, cand_rows, space, crit);
    if (!exchanged && !refined && !retilted) break;
  }

  DesignSummary out;
  out.level_poses = level;
  out.min_height_relaxed = !opts.min_height.has_value() && o.min_height.has_value();
  out.plan = order_plan(w.poses);
  const Samples plan = to_samples(out.plan, model.num_joints());
  // The expected error is over every feasible pose: any tilt in the cone, not
  // only the plan's tilt groups (as evaluate_plan sees the plan too).
  DesignOptions anywhere = opts;
  anywhere.tilt_groups = 0;
  DesignSpace feasible(model, anywhere);
  figures(model, base, plan, o, feasible, out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

Clearance lowest_clearance(const Model& model, const DesignOptions& options,
                           const Samples& samples) {
  DesignOptions o = options;
  o.tilt_max.reset();
  o.tilts.clear();
  DesignSpace space(model, o);
  Clearance c;
  c.height = kInfinity;
  for (int r = 0; r < samples.q.rows(); ++r) {
    int link = -1;
    const double h = space.clearance(samples.q.row(r).transpose(), &link);
    if (h < c.height) {
      c.height = h;
      c.row = r;
      c.link = link >= 0 ? model.links[link].name : "";
    }
  }
  return c;
}

DesignSummary evaluate_plan(const Model& model, const BaseParameters& base, const Samples& plan,
                            const DesignOptions& o) {
  DesignOptions opts = o;
  // A wrist's plan with the arm's columns: random arm poses for the expected
  // error (no tilts); without them the arm is held (gravity from the file).
  opts.move_arm = opts.move_arm && model.num_upstream_joints() > 0 && plan.q_upstream.cols() > 0;
  DesignSummary out;
  for (int i = 0; i < plan.size(); ++i) {
    PlanPose pose;
    pose.q = plan.q.row(i).transpose();
    pose.gravity = plan.gravity.row(i).transpose();
    if (opts.move_arm) pose.q_upstream = plan.q_upstream.row(i).transpose();
    out.plan.push_back(pose);
  }
  // Random poses for the expected error: the file's largest tilt unless given.
  if (!opts.move_arm && !opts.tilt_max && opts.tilts.empty()) {
    double largest = 0.0;
    for (const PlanPose& p : out.plan)
      largest = std::max(largest, std::atan2(p.gravity.cross(opts.level_gravity).norm(),
                                             p.gravity.dot(opts.level_gravity)));
    // A level far from the file's gravity (say the default -z for a sensor
    // mounted upside down): take the file's mean gravity direction as level.
    if (largest >= std::numbers::pi / 2 - 1e-6) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const PlanPose& p : out.plan) mean += p.gravity.normalized();
      if (mean.norm() > 1e-9) {
        opts.level_gravity = mean.normalized() * opts.level_gravity.norm();
        largest = 0.0;
        for (const PlanPose& p : out.plan)
          largest = std::max(largest, std::atan2(p.gravity.cross(opts.level_gravity).norm(),
                                                 p.gravity.dot(opts.level_gravity)));
      }
    }
    opts.tilt_max = std::min(largest, 89.0 * std::numbers::pi / 180.0);
  }
  opts.tilt_groups = 0;  // random poses: any tilt in the cone
  DesignSpace space(model, opts);
  space.relax_min_height_if_infeasible(opts.min_height_required);
  out.min_height_relaxed = space.min_height_relaxed();
  figures(model, base, plan, opts, space, out);
  return out;
}

}  // namespace massid

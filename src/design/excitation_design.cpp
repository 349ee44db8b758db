// design_excitation (excitation.hpp): the Hooke-Jeeves search over the
// Fourier coefficients of an exciting trajectory, on the criterion of
// design_criterion.hpp, within the joints' limits and above the platform;
// and random_fourier_trajectory and sample_trajectory, which share the
// search's limits and sampling.
#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>

#include "core/median.hpp"
#include "design/arm_clearance.hpp"
#include "design/design_criterion.hpp"
#include "design/design_space.hpp"
#include "massid/core/errors.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identifiability.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {
namespace {

using detail::median;

constexpr double kNoLimit = std::numeric_limits<double>::infinity();
// A trajectory below the minimum height ranks behind every one above it:
// its score is this plus its deficit in mm (criterion scores are logs).
constexpr double kInfeasible = 1e6;

// What one joint may do: positions [lo, hi] (a margin inside the limits),
// |q - q0| <= amplitude when unlimited, |qd| <= velocity, |qdd| <= acceleration.
struct JointBounds {
  bool limited = false;
  double lo = 0.0, hi = 0.0, amplitude = 0.0, velocity = 0.0, acceleration = 0.0;
};

std::vector<JointBounds> joint_bounds(const std::vector<Joint>& joints,
                                      const ExcitationLimits& limits) {
  std::vector<JointBounds> out;
  for (size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    JointBounds b;
    b.limited = joint.limited;
    const double margin = limits.position_margin * (joint.upper - joint.lower);
    b.lo = joint.lower + margin;
    b.hi = joint.upper - margin;
    b.amplitude = limits.unlimited_amplitude;
    b.velocity = joint.velocity_limit > 0 ? joint.velocity_limit : limits.default_velocity;
    b.acceleration = j < limits.joint_acceleration.size() && limits.joint_acceleration[j] > 0
                         ? limits.joint_acceleration[j]
                         : limits.acceleration;
    out.push_back(b);
  }
  return out;
}

// Per joint, the largest factor s such that q0 + s (q(t) - q0), s qd(t) and
// s qdd(t) keep within the bounds at every given time (the trajectory is
// linear in its coefficients, so scaling them scales the three alike).
Eigen::VectorXd limit_scale(const FourierTrajectory& tr, const std::vector<JointBounds>& bounds,
                            const Eigen::VectorXd& times) {
  const int nj = tr.num_joints();
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(nj), down = up, vel = up, acc = up;
  for (Eigen::Index i = 0; i < times.size(); ++i) {
    tr.evaluate(times[i], q, qd, qdd);
    up = up.cwiseMax(q - tr.q0);
    down = down.cwiseMax(tr.q0 - q);
    vel = vel.cwiseMax(qd.cwiseAbs());
    acc = acc.cwiseMax(qdd.cwiseAbs());
  }
  Eigen::VectorXd s(nj);
  for (int j = 0; j < nj; ++j) {
    const JointBounds& b = bounds[j];
    const auto ratio = [](double room, double used) {
      return used > 0.0 ? std::max(room, 0.0) / used : kNoLimit;
    };
    double x = std::min(ratio(b.velocity, vel[j]), ratio(b.acceleration, acc[j]));
    if (b.limited)
      x = std::min({x, ratio(b.hi - tr.q0[j], up[j]), ratio(tr.q0[j] - b.lo, down[j])});
    else
      x = std::min({x, ratio(b.amplitude, up[j]), ratio(b.amplitude, down[j])});
    s[j] = std::isfinite(x) ? x : 1.0;  // a joint that does not move
  }
  return s;
}

// Joint j's coefficients times s[j] (q0 stays).
void scale_joints(FourierTrajectory& tr, const Eigen::VectorXd& s) {
  tr.a.array().colwise() *= s.array();
  tr.b.array().colwise() *= s.array();
}

// The search's coordinates x of a trajectory, per joint: the free
// coefficients (a_2..a_K, b_2..b_K; one harmonic: b_1), the centre as a
// fraction of the limited range (-1..1; 0 for an unlimited joint) and the
// amplitude as a fraction of what the limits allow (0.05..1).
class Coordinates {
 public:
  Coordinates(const std::vector<JointBounds>& bounds, int harmonics, double period)
      : bounds_(bounds), K_(harmonics), period_(period) {}
  int per_joint() const { return free_coefficients() + 2; }
  int dimension() const { return per_joint() * static_cast<int>(bounds_.size()); }

  Eigen::VectorXd of(const FourierTrajectory& tr) const {
    Eigen::VectorXd x(dimension());
    for (int j = 0; j < tr.num_joints(); ++j) {
      auto xj = x.segment(j * per_joint(), per_joint());
      if (K_ == 1) {
        xj[0] = tr.b(j, 0);
      } else {
        xj.head(K_ - 1) = tr.a.row(j).tail(K_ - 1).transpose();
        xj.segment(K_ - 1, K_ - 1) = tr.b.row(j).tail(K_ - 1).transpose();
      }
      const JointBounds& b = bounds_[j];
      xj[per_joint() - 2] =
          b.limited && b.hi > b.lo ? (2.0 * tr.q0[j] - b.lo - b.hi) / (b.hi - b.lo) : 0.0;
      xj[per_joint() - 1] = 1.0;
    }
    return x;
  }

  // The trajectory at x, before scaling: at rest at t = 0 by
  // a_1 = -sum_{k>1} a_k (q_dot(0) = sum_k a_k = 0) and
  // b_1 = -sum_{k>1} k b_k (q_ddot(0) = w sum_k k b_k = 0).
  FourierTrajectory raw(const Eigen::VectorXd& x) const {
    const int nj = static_cast<int>(bounds_.size());
    FourierTrajectory tr;
    tr.period = period_;
    tr.q0.resize(nj);
    tr.a = Eigen::MatrixXd::Zero(nj, K_);
    tr.b = Eigen::MatrixXd::Zero(nj, K_);
    for (int j = 0; j < nj; ++j) {
      const auto xj = x.segment(j * per_joint(), per_joint());
      if (K_ == 1) {
        tr.b(j, 0) = xj[0];
      } else {
        tr.a.row(j).tail(K_ - 1) = xj.head(K_ - 1).transpose();
        tr.b.row(j).tail(K_ - 1) = xj.segment(K_ - 1, K_ - 1).transpose();
        tr.a(j, 0) = -tr.a.row(j).tail(K_ - 1).sum();
        double kb = 0.0;
        for (int k = 2; k <= K_; ++k) kb += k * tr.b(j, k - 1);
        tr.b(j, 0) = -kb;
      }
      const JointBounds& b = bounds_[j];
      const double centre = std::clamp(xj[per_joint() - 2], -0.95, 0.95);
      tr.q0[j] = b.limited ? 0.5 * (b.lo + b.hi) + 0.5 * (b.hi - b.lo) * centre : 0.0;
    }
    return tr;
  }

  double amplitude(const Eigen::VectorXd& x, int j) const {
    return std::clamp(x[j * per_joint() + per_joint() - 1], 0.05, 1.0);
  }
  // x with every joint's amplitude fraction set to u.
  Eigen::VectorXd with_amplitude(Eigen::VectorXd x, double u) const {
    for (size_t j = 0; j < bounds_.size(); ++j) x[j * per_joint() + per_joint() - 1] = u;
    return x;
  }

  // Initial steps: a fifth of each coefficient's scale (they fall as 1/k),
  // a tenth of the range for the centre, a fifth for the amplitude.
  Eigen::VectorXd steps(const Eigen::VectorXd& x) const {
    Eigen::VectorXd s(dimension());
    for (size_t j = 0; j < bounds_.size(); ++j) {
      auto sj = s.segment(j * per_joint(), per_joint());
      const auto xj = x.segment(j * per_joint(), free_coefficients());
      const double scale = std::max(xj.cwiseAbs().maxCoeff(), 1e-12);
      sj.head(free_coefficients()).setConstant(0.2 * scale);
      sj[per_joint() - 2] = bounds_[j].limited ? 0.1 : 0.0;
      sj[per_joint() - 1] = 0.2;
    }
    return s;
  }

 private:
  int free_coefficients() const { return K_ == 1 ? 1 : 2 * (K_ - 1); }
  const std::vector<JointBounds>& bounds_;
  int K_;
  double period_;
};

// The trajectory at `times` (s): t, q, qd, qdd, `gravity` in every row, lines from 1.
Samples trajectory_at(const FourierTrajectory& tr, const Eigen::VectorXd& times,
                      const Eigen::Vector3d& gravity) {
  const int n = static_cast<int>(times.size()), nj = tr.num_joints();
  Samples s;
  s.source = "trajectory";
  for (Eigen::MatrixXd* m : {&s.q, &s.qd, &s.qdd}) m->resize(n, nj);
  s.gravity = gravity.transpose().replicate(n, 1);
  s.time = times;
  s.line.resize(n);
  std::iota(s.line.begin(), s.line.end(), 1);
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  for (int i = 0; i < n; ++i) {
    tr.evaluate(times[i], q, qd, qdd);
    s.q.row(i) = q.transpose();
    s.qd.row(i) = qd.transpose();
    s.qdd.row(i) = qdd.transpose();
  }
  return s;
}

// `one` once for every block's gravity, the blocks one after the other: t
// continues (block b starts at b block_time), lines number the rows, `block`
// the blocks from 0 (none for one block).
Samples per_block(const Samples& one, const std::vector<Eigen::Vector3d>& gravities,
                  double block_time) {
  const int n = one.size(), blocks = static_cast<int>(gravities.size());
  Samples s = one;
  s.q = one.q.replicate(blocks, 1);
  s.qd = one.qd.replicate(blocks, 1);
  s.qdd = one.qdd.replicate(blocks, 1);
  s.gravity.resize(n * blocks, 3);
  s.time.resize(n * blocks);
  s.line.resize(n * blocks);
  std::iota(s.line.begin(), s.line.end(), 1);
  for (int b = 0; b < blocks; ++b) {
    s.gravity.middleRows(b * n, n).rowwise() = gravities[b].transpose();
    s.time.segment(b * n, n) = b * block_time + one.time.array();
    if (blocks > 1) s.block.insert(s.block.end(), n, b);
  }
  return s;
}

// Samples over trajectory_joints(model) -> the model's: a wrist's first
// columns become the upstream joints, whose kinematics give gravity and the
// sensor frame's motion (resolve_upstream, as the readers do).
Samples arm_samples(const Model& model, Samples s, const ExcitationOptions& o) {
  const int nu = model.num_upstream_joints(), nj = model.num_joints();
  if (nu == 0 || !o.move_arm) return s;
  s.q_upstream = s.q.leftCols(nu);
  s.qd_upstream = s.qd.leftCols(nu);
  s.qdd_upstream = s.qdd.leftCols(nu);
  for (Eigen::MatrixXd* m : {&s.q, &s.qd, &s.qdd}) {
    Eigen::MatrixXd own = m->rightCols(nj);
    *m = std::move(own);
  }
  s.root_gravity = o.root_gravity;
  s.gravity_from_upstream = true;
  s.gravity.resize(s.size(), 3);
  s.sensor_motion.resize(0, 0);
  resolve_upstream(model, s);
  return s;
}

// The information matrix of the rows of s (every block); R: a workspace
// [num_rows x size].
Eigen::MatrixXd information_of(CriterionRows& crit, const Samples& s, Eigen::MatrixXd& R) {
  Eigen::MatrixXd info = Eigen::MatrixXd::Zero(crit.size(), crit.size());
  for (int i = 0; i < s.size(); ++i) {
    crit.rows(s.q.row(i).transpose(), s.qd.row(i).transpose(), s.qdd.row(i).transpose(),
              s.gravity.row(i).transpose(), sensor_motion(s, i), R);
    info.selfadjointView<Eigen::Lower>().rankUpdate(R.transpose());
  }
  return info.selfadjointView<Eigen::Lower>();
}

// A wrist's tool alone: the measured links as one rigid body, their joints
// held at the trajectory's centre; the condition number of its parameters
// (and the offsets) over the samples, and how many.
std::pair<double, int> tool_condition(const Model& model, const BaseParameters& base,
                                      const FourierTrajectory& tr, Samples s,
                                      const ExcitationOptions& o) {
  std::vector<std::pair<std::string, double>> held;
  for (int j = 0; j < model.num_joints(); ++j)
    held.emplace_back(model.joints[j].name, tr.q0[model.num_upstream_joints() + j]);
  const Model rigid = hold_joints(model, held);
  BaseParameterOptions bo;
  bo.layout = ParameterLayout::full();
  bo.sensor_moving = true;
  bo.offset = base.offset;
  const BaseParameters tool = find_base_parameters(rigid, bo);
  for (Eigen::MatrixXd* m : {&s.q, &s.qd, &s.qdd}) m->resize(s.size(), 0);
  CriterionRows crit(rigid, tool, Criterion::Cond, o.noise_force, o.noise_moment);
  Eigen::MatrixXd R(crit.num_rows(), crit.size());
  return {crit.figure(crit.value(information_of(crit, s, R))), tool.num_unknowns()};
}

// Where a trajectory misses its clearances the most: by how much (m; <= 0:
// it keeps them), at which row, and what.
struct Miss {
  double deficit = -kNoLimit;
  int row = -1;
  std::string what;
};

// The criterion of a trajectory on the grid, for every block's gravity.
class GridCriterion {
 public:
  GridCriterion(const Model& model, const BaseParameters& base, const ExcitationOptions& o,
                const std::vector<JointBounds>& bounds, const Eigen::VectorXd& grid)
      : model_(model),
        crit_(model, base, o.criterion, o.noise_force, o.noise_moment),
        bounds_(bounds),
        grid_(grid),
        gravities_(block_gravities(o)),
        options_(o),
        R_(crit_.num_rows(), crit_.size()) {
    design_.level_gravity = o.level_gravity;
    design_.min_height = o.min_height;
    if (model.num_upstream_joints() > 0 && o.move_arm) arm_.emplace(model, o.root_gravity);
  }

  // The trajectory of x scaled to the limits on the grid.
  FourierTrajectory scaled(const Coordinates& coords, const Eigen::VectorXd& x) const {
    FourierTrajectory tr = coords.raw(x);
    Eigen::VectorXd s = limit_scale(tr, bounds_, grid_);
    for (int j = 0; j < tr.num_joints(); ++j) s[j] *= coords.amplitude(x, j);
    scale_joints(tr, s);
    return tr;
  }

  // Lower is better: kInfeasible + deficit (mm) below min_height + margin on
  // the grid, else the criterion value's log (+inf when singular).
  double score(const FourierTrajectory& tr, double margin = 0.0) {
    ++evaluations_;
    const Samples s = sample(tr);
    if (const double d = miss(s, margin).deficit; d > 0.0) return kInfeasible + 1e3 * d;
    // cond: the log of the eigenvalue ratio; d-opt: -log det as it is.
    const double v = crit_.value(information(s));
    if (!std::isfinite(v)) return kInfeasible / 2;
    return crit_.criterion() == Criterion::DOpt ? v : std::log(v);
  }

  // The largest miss of the clearances over the rows of s, `margin` more
  // each: the height above the platform plane, or for a wrist above the floor
  // and the arm's self-clearance (arm_clearance.hpp).
  Miss miss(const Samples& s, double margin) {
    const std::optional<double>& min_height = options_.min_height;
    const std::optional<double>& self_clearance = options_.self_clearance;
    Miss out;
    if (!arm_) {
      if (!min_height) return out;
      const Clearance c = lowest_clearance(model_, design_, s);
      return {*min_height + margin - c.height, c.row,
              fmt::format("takes link '{}' to {:.3g} m above the platform plane, below the "
                          "clearance of {} m",
                          c.link, c.height, *min_height)};
    }
    int worst_row = -1;
    ArmClearanceValue worst;
    bool low = false;
    for (int i = 0; i < s.size(); ++i) {
      const ArmClearanceValue v = arm_->at(s.q_upstream.row(i).transpose(), s.q.row(i).transpose());
      if (min_height && *min_height + margin - v.height > out.deficit)
        out.deficit = *min_height + margin - v.height, worst_row = i, worst = v, low = true;
      if (self_clearance && *self_clearance + margin - v.self > out.deficit)
        out.deficit = *self_clearance + margin - v.self, worst_row = i, worst = v, low = false;
    }
    out.row = worst_row;
    if (worst_row >= 0)
      out.what = low ? fmt::format("takes {} to {:.3g} m above the floor, below --min-height {} m",
                                   worst.low_link, worst.height, *min_height)
                     : fmt::format(
                           "brings {} within {:.3g} m of each other, below "
                           "--self-clearance {} m",
                           worst.self_pair, worst.self, *self_clearance);
    return out;
  }

  // A wrist's lowest point above the floor and least self-clearance over s.
  ArmClearanceValue arm_clearance(const Samples& s) {
    ArmClearanceValue out{kNoLimit, "", kNoLimit, ""};
    for (int i = 0; arm_ && i < s.size(); ++i) {
      const ArmClearanceValue v = arm_->at(s.q_upstream.row(i).transpose(), s.q.row(i).transpose());
      if (v.height < out.height) out.height = v.height, out.low_link = v.low_link;
      if (v.self < out.self) out.self = v.self, out.self_pair = v.self_pair;
    }
    return out;
  }

  // The information matrix of the given rows (every block).
  Eigen::MatrixXd information(const Samples& s) { return information_of(crit_, s, R_); }

  // The grid's samples of every block (the blocks share their times: nothing reads them).
  Samples sample(const FourierTrajectory& tr) const {
    Samples s = per_block(trajectory_at(tr, grid_, gravities_[0]), gravities_, 0.0);
    s.source = "the exciting trajectory";
    return arm_samples(model_, std::move(s), options_);
  }

  const CriterionRows& criterion() const { return crit_; }
  int evaluations() const { return evaluations_; }
  const DesignOptions& clearance_options() const { return design_; }

 private:
  const Model& model_;
  CriterionRows crit_;
  const std::vector<JointBounds>& bounds_;
  Eigen::VectorXd grid_;
  std::vector<Eigen::Vector3d> gravities_;
  ExcitationOptions options_;
  std::optional<ArmClearance> arm_;  // a wrist
  DesignOptions design_;             // level gravity and min_height, for lowest_clearance
  Eigen::MatrixXd R_;
  int evaluations_ = 0;
};

// Hooke-Jeeves pattern search from x (score fx) within `budget` scores:
// exploratory moves along each coordinate (+step, then -step), then pattern
// moves along the last gain while they pay; steps halve when nothing gains.
void pattern_search(const Coordinates& coords, GridCriterion& grid, Eigen::VectorXd& x, double& fx,
                    int budget, double margin) {
  const int start = grid.evaluations();
  Eigen::VectorXd step = coords.steps(x);
  const Eigen::VectorXd first = step;
  const auto left = [&] { return grid.evaluations() - start < budget; };
  const auto explore = [&](Eigen::VectorXd& y, double& fy) {
    for (Eigen::Index d = 0; d < y.size() && left(); ++d) {
      if (step[d] <= 0.0) continue;
      for (const double sign : {1.0, -1.0}) {
        Eigen::VectorXd z = y;
        z[d] += sign * step[d];
        const double fz = grid.score(grid.scaled(coords, z), margin);
        if (fz < fy) {
          y = std::move(z);
          fy = fz;
          break;
        }
      }
    }
  };
  while (left() && (step.array() > 1e-3 * first.array()).any()) {
    Eigen::VectorXd y = x;
    double fy = fx;
    explore(y, fy);
    if (!(fy < fx)) {
      step *= 0.5;
      continue;
    }
    // Pattern moves: x -> y, try y + (y - x) and explore around it.
    while (left()) {
      Eigen::VectorXd z = y + (y - x);
      x = y;
      fx = fy;
      double fz = grid.score(grid.scaled(coords, z), margin);
      explore(z, fz);
      if (!(fz < fx)) break;
      y = std::move(z);
      fy = fz;
    }
  }
}

// The trajectory sampled at the written rate, every block one after the
// other (per_block: a block starts one sample period after the previous ends).
Samples written_samples(const Model& model, const FourierTrajectory& tr,
                        const ExcitationOptions& o) {
  const std::vector<Eigen::Vector3d> gravities = block_gravities(o);
  const Samples one = sample_trajectory(tr, o.duration, o.rate, gravities[0]);
  return arm_samples(model, per_block(one, gravities, (one.size() - 1) / o.rate + 1.0 / o.rate), o);
}

}  // namespace

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
  scale_joints(tr, limit_scale(tr, joint_bounds(joints, limits),
                               Eigen::VectorXd::LinSpaced(grid, 0.0, grid - 1.0) * period / grid));
  return tr;
}

Samples sample_trajectory(const FourierTrajectory& tr, double duration, double rate,
                          const Eigen::Vector3d& gravity) {
  const int n = static_cast<int>(std::floor(duration * rate + 1e-9)) + 1;
  return trajectory_at(tr, Eigen::VectorXd::LinSpaced(n, 0.0, n - 1.0) / rate, gravity);
}

std::vector<Eigen::Vector3d> block_gravities(const ExcitationOptions& o) {
  if (o.tilts.empty()) return {o.level_gravity};
  std::vector<Eigen::Vector3d> out;
  for (const Tilt& t : o.tilts) out.push_back(tilted_gravity(o.level_gravity, t));
  return out;
}

ExcitationSummary design_excitation(const Model& model, const BaseParameters& base,
                                    const ExcitationOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (!(o.level_gravity.norm() > 0.0))
    throw InputError("design: the level gravity vector is zero",
                     {{Hint::Setting::LevelGravity, ""}});
  const int K = std::max(1, o.harmonics);
  const bool wrist = model.num_upstream_joints() > 0 && o.move_arm;
  if (wrist && !o.tilts.empty())
    throw InputError(
        "design in motion: a sensor below movable joints (a wrist) takes gravity from the arm's "
        "joints and the root gravity: no platform tilts");
  const std::vector<Joint> joints = wrist ? trajectory_joints(model) : model.joints;
  const std::vector<JointBounds> bounds = joint_bounds(joints, o.limits);
  ExcitationSummary out;
  ExcitationOptions opts = o;
  if (o.min_height && !wrist) {  // the default height is dropped when no pose at all satisfies it
    DesignOptions d;
    d.level_gravity = o.level_gravity;
    d.min_height = o.min_height;
    DesignSpace probe(model, d);
    probe.relax_min_height_if_infeasible(o.min_height_required);
    out.min_height_relaxed = probe.min_height_relaxed();
    if (out.min_height_relaxed) opts.min_height.reset();
  }

  // The criterion's grid: one period when the duration is a whole number of
  // them (the information of m periods is m times one period's), else the
  // whole duration.
  out.grid_rate =
      o.grid_rate > 0 ? o.grid_rate : std::min(o.rate, std::max(20.0, 20.0 * K / o.period));
  const double periods = o.duration / o.period;
  const bool whole = periods >= 1.0 - 1e-9 && std::abs(periods - std::round(periods)) < 1e-9;
  out.at_rest_at_end = whole || K == 1;
  const double window = whole ? o.period : o.duration;
  const int n = std::max(2, static_cast<int>(std::ceil(window * out.grid_rate - 1e-9)));
  const Eigen::VectorXd grid =
      Eigen::VectorXd::LinSpaced(n, 0.0, window * (whole ? (n - 1.0) / n : 1.0));

  GridCriterion crit(model, base, opts, bounds, grid);
  const Coordinates coords(bounds, K, o.period);
  const CriterionRows& rows = crit.criterion();

  // Random starts (and the baseline): the first `candidates` start, the
  // first `random_baseline` give the median.
  const int randoms = std::max({1, o.candidates, o.random_baseline});
  Eigen::VectorXd x;
  double fx = kNoLimit;
  std::vector<double> baseline;
  for (int c = 0; c < randoms; ++c) {
    const FourierTrajectory tr =
        random_fourier_trajectory(joints, K, o.period, o.seed + 7919u * c, o.limits);
    const Eigen::VectorXd xc = coords.of(tr);
    const FourierTrajectory scaled = crit.scaled(coords, xc);
    if (c < o.random_baseline) {
      // The baseline's figure without the clearance: random coefficients
      // scaled to the same joint limits.
      baseline.push_back(rows.figure(rows.value(crit.information(crit.sample(scaled)))));
    }
    if (c >= std::max(1, o.candidates)) continue;
    const double f = crit.score(scaled);
    if (f < fx || c == 0) x = xc, fx = f;
  }
  // A start below the minimum height: the largest common amplitude fraction
  // that keeps it (the search then widens each joint as the height allows).
  for (const double u : {0.7, 0.5, 0.35, 0.25, 0.15, 0.1, 0.05}) {
    if (fx < kInfeasible) break;
    const Eigen::VectorXd xu = coords.with_amplitude(x, u);
    const double f = crit.score(crit.scaled(coords, xu));
    if (f < fx) x = xu, fx = f;
  }
  out.random_median = median(baseline);
  out.random_count = static_cast<int>(baseline.size());
  out.start_figure = fx < kInfeasible / 2  // a score is log cond, or -log det
                         ? rows.figure(rows.criterion() == Criterion::DOpt ? fx : std::exp(fx))
                         : kNoLimit;

  // The search, then the written samples: shrink where a sample exceeds a
  // limit, and check the clearance; a miss between grid points reruns the
  // search with that much more margin.
  double margin = 0.0;
  FourierTrajectory best;
  for (int round = 0;; ++round) {
    pattern_search(coords, crit, x, fx, round == 0 ? o.evaluations : o.evaluations / 4, margin);
    if (fx >= kInfeasible)
      throw InputError(fmt::format("design in motion: no trajectory found keeps {} (the "
                                   "clearance; the best misses by "
                                   "{:.3g} m): lower the clearance, narrow the joints' ranges, or "
                                   "turn the clearance off",
                                   wrist ? fmt::format("the arm's moving points {} m above the "
                                                       "floor and its links {} m apart",
                                                       opts.min_height.value_or(0.0),
                                                       opts.self_clearance.value_or(0.0))
                                         : fmt::format("every moving link origin, centre of "
                                                       "mass and collision sphere {} m above the "
                                                       "platform plane",
                                                       opts.min_height.value_or(0.0)),
                                   (fx - kInfeasible) / 1e3),
                       {{Hint::Setting::MinHeight, "lower"},
                        {Hint::Setting::Limits, ""},
                        {Hint::Setting::MinHeight, "none"}});
    best = crit.scaled(coords, x);
    const Samples one = sample_trajectory(best, o.duration, o.rate, o.level_gravity);
    scale_joints(best, limit_scale(best, bounds, one.time).cwiseMin(1.0));
    const Miss c = crit.miss(
        arm_samples(model, sample_trajectory(best, o.duration, o.rate, o.level_gravity), o), 0.0);
    if (!(c.deficit > 0.0)) break;
    if (round == 3)
      throw InputError(fmt::format("design in motion: the trajectory {} at t = {:.4g} s, after 4 "
                                   "searches with growing margins: lower the clearance or narrow "
                                   "the joints' ranges",
                                   c.what, c.row / o.rate),
                       {{Hint::Setting::MinHeight, "lower"}, {Hint::Setting::Limits, ""}});
    margin += c.deficit + 1e-3;
    fx = crit.score(crit.scaled(coords, x), margin);
  }
  out.trajectory = best;
  out.evaluations = crit.evaluations();
  out.grid_figure = rows.figure(rows.value(crit.information(crit.sample(best))));
  const Samples written = written_samples(model, best, o);

  // Figures of the written samples: every row, noise-weighted.
  const Eigen::MatrixXd info = crit.information(written);
  const CriterionRows cond(model, base, Criterion::Cond, o.noise_force, o.noise_moment);
  out.condition_number = cond.figure(cond.value(info));
  const CriterionRows dopt(model, base, Criterion::DOpt, o.noise_force, o.noise_moment);
  out.log_det = dopt.figure(dopt.value(info));
  if (wrist) {
    const ArmClearanceValue c = crit.arm_clearance(written);
    out.lowest_clearance = c.height;
    out.lowest_link = c.low_link;
    out.lowest_self_clearance = c.self;
    out.self_pair = c.self_pair;
  } else {
    const Clearance c = lowest_clearance(model, crit.clearance_options(), written);
    out.lowest_clearance = c.height;
    out.lowest_link = c.link;
  }
  const Samples on_grid = crit.sample(best);
  Eigen::MatrixXd A = stacked_regressor(model, base, on_grid);
  const IdentifiabilityReport report = check_identifiability(model, base, on_grid, A, 1e-9);
  out.identifiable = report.ok();
  out.identifiability_message = report.message;
  const int p = base.num_unknowns();
  out.predicted_std = Eigen::VectorXd::Constant(p, kNoLimit);
  if (out.identifiable) {
    Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
    out.predicted_std = ldlt.solve(Eigen::MatrixXd::Identity(p, p)).diagonal().cwiseSqrt();
  }
  if (wrist && model.num_joints() > 0)
    std::tie(out.tool_condition_number, out.tool_parameters) =
        tool_condition(model, base, best, written, o);
  out.samples = written;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace massid

// Exciting trajectories for identification in motion: a finite Fourier series
// per joint (Swevers, Ganseman, Tukel, De Schutter & Van Brussel 1997),
//
//   q_j(t)   = q0_j + sum_k ( a_jk sin(k w t) - b_jk cos(k w t) ) / (k w)
//   qd_j(t)  = sum_k a_jk cos(k w t) + b_jk sin(k w t)
//   qdd_j(t) = sum_k k w ( b_jk cos(k w t) - a_jk sin(k w t) )
//
// with w = 2 pi / period. Periodic, so the data of whole periods average the
// noise evenly; at rest at t = 0 (and every period) by the constraints
// sum_k a_jk = 0 and sum_k k b_jk = 0; scaled into the joints' position
// limits (a margin inside), velocity limits and acceleration limits.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/design/design.hpp"

namespace massid {

struct FourierTrajectory {
  double period = 10.0;  // s
  Eigen::VectorXd q0;    // [num_joints] centre position
  Eigen::MatrixXd a, b;  // [num_joints x harmonics] coefficients, rad/s (m/s)

  int num_joints() const { return static_cast<int>(q0.size()); }
  int harmonics() const { return static_cast<int>(a.cols()); }
  // Position, velocity and acceleration at time t, each [num_joints].
  void evaluate(double t, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                Eigen::Ref<Eigen::VectorXd> qdd) const;
};

struct ExcitationLimits {
  double position_margin = 0.1;   // fraction of each limited joint's range kept free at each end
  double default_velocity = 1.0;  // rad/s or m/s when the URDF gives no velocity limit
  double acceleration = 4.0;      // rad/s^2 or m/s^2, every joint ...
  std::vector<double> joint_acceleration;  // ... or per joint [num_joints] where > 0
  double unlimited_amplitude = 1.5;        // rad (m) about q0 for joints without position limits
};

// Random coefficients (Gaussian, falling as 1/k), made to start at rest,
// scaled to the limits: the baseline exciting trajectory, over the model's
// joints or the given ones.
FourierTrajectory random_fourier_trajectory(const Model& model, int harmonics, double period,
                                            std::uint64_t seed,
                                            const ExcitationLimits& limits = {});
FourierTrajectory random_fourier_trajectory(const std::vector<Joint>& joints, int harmonics,
                                            double period, std::uint64_t seed,
                                            const ExcitationLimits& limits = {});

// The joints an exciting trajectory moves: those above the sensor link
// (Model::upstream_joints, a wrist sensor: they move the tool), then the
// model's own. FourierTrajectory's joints are in this order.
std::vector<Joint> trajectory_joints(const Model& model);

// The trajectory sampled at `rate` Hz over [0, duration]: t, q, qd, qdd, and
// the given gravity (sensor frame) in every row; lines numbered from 1.
Samples sample_trajectory(const FourierTrajectory& trajectory, double duration, double rate,
                          const Eigen::Vector3d& gravity);

// The exciting trajectory that minimises the design criterion (design.hpp:
// cond, the condition number of the column-scaled, noise-weighted dynamic
// base regressor that identify reports in motion, or d-opt) over the
// Fourier coefficients, the centre q0 and a per-joint amplitude, within the
// limits, run once per platform tilt (a block each, gravity fixed in a block).
//
// Method: `candidates` random trajectories (random_fourier_trajectory), the
// best by the criterion is the start of a Hooke-Jeeves pattern search of
// `evaluations` criterion evaluations. Every trajectory the search sees is at
// rest at t = 0 (q_dot = q_ddot = 0: sum_k a_k = 0, sum_k k b_k = 0; one
// harmonic: q_dot only) and scaled per joint to the tightest of its limits on
// the criterion's grid (`grid_rate`, over one period when the duration is a
// whole number of periods); a trajectory that takes a checked point below
// min_height there ranks behind every one that does not (by its deficit).
// The result is then sampled at `rate` and shrunk per joint where a written
// sample would exceed a limit, and its clearance is checked on the written
// samples (the search is rerun with a larger margin when it misses).
// Deterministic per seed.
struct ExcitationOptions {
  int harmonics = 5;
  double period = 10.0;      // s
  double duration = 30.0;    // s, per block
  double rate = 1000.0;      // Hz of the written trajectory
  int candidates = 8;        // random starts
  int evaluations = 6000;    // criterion evaluations of the search; 0: the best random start
  int random_baseline = 20;  // random trajectories whose median criterion is reported (0: none)
  double grid_rate = 0.0;    // Hz of the criterion's grid; 0: automatic (20 samples per period
                             // of the highest harmonic, at least 20 Hz, at most `rate`)
  std::uint64_t seed = 1;
  Eigen::Vector3d level_gravity{0.0, 0.0, -kStandardGravity};  // sensor frame, platform level
  std::vector<Tilt> tilts;  // a block per tilt, in this order; empty: one level block
  Criterion criterion = Criterion::Cond;
  double noise_force = 0.1;    // N, for the criterion and the predicted std
  double noise_moment = 0.01;  // N m
  ExcitationLimits limits;
  // m: every moving link origin, centre of mass and collision sphere at least
  // this far above the platform plane (design.hpp DesignOptions::min_height);
  // nullopt: no constraint.
  std::optional<double> min_height;
  // false: when no pose at all satisfies min_height (a sensor link below the
  // mount, say), go on without it (ExcitationSummary::min_height_relaxed);
  // true (the CLI's explicit --min-height): InputError.
  bool min_height_required = false;
  // A wrist (a sensor link below movable joints, Model::upstream_joints): the
  // trajectory moves the arm's joints too (trajectory_joints); gravity and the
  // sensor frame's motion follow from them and `root_gravity` (URDF root
  // frame; `level_gravity` and `tilts` do not apply). min_height is then the height
  // above the floor, the plane through the root origin normal to root_gravity,
  // of the arm's moving link origins and the tool's points, and
  // self_clearance the least distance between the centre lines of two arm
  // links that no single link joins (src/design/arm_clearance.hpp); nullopt:
  // not checked.
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
  std::optional<double> self_clearance = kDefaultSelfClearance;
  // false: the arm is held still, the trajectory moves the joints below the
  // sensor with gravity from `level_gravity` and `tilts` (DesignOptions::move_arm).
  bool move_arm = true;
};

// Gravity (sensor frame) of each block: the tilts applied to the level
// gravity, or the level gravity alone.
std::vector<Eigen::Vector3d> block_gravities(const ExcitationOptions& options);

struct ExcitationSummary {
  FourierTrajectory trajectory;
  Samples samples;                // as written: every block at `rate`, t continuous, block
  double condition_number = 0.0;  // of the written samples, as identify reports it in motion
  double log_det = 0.0;           // log det of the noise-weighted information, written samples
  double grid_figure = 0.0;       // the criterion's figure on its grid (cond, or log det)
  double random_median = 0.0;     // the same figure, median over the random trajectories
  int random_count = 0;           // how many (0: not computed)
  double start_figure = 0.0;      // the best random start's figure
  int evaluations = 0;            // criterion evaluations made
  double seconds = 0.0;           // design time
  double grid_rate = 0.0;         // Hz
  double lowest_clearance = 0.0;  // m over the written samples (+inf: nothing moves)
  std::string lowest_link;
  bool min_height_relaxed = false;  // no pose satisfies min_height: not constrained
  bool at_rest_at_end = false;      // duration a whole number of periods (or one harmonic: q_dot)
  Eigen::VectorXd predicted_std;    // [num_unknowns] at the noise, the written samples
  bool identifiable = false;
  std::string identifiability_message;
  // A wrist: the arm's least self-clearance over the written samples (m) and
  // the two links; the condition number (as condition_number) of the tool
  // alone, the measured links as one rigid body at the trajectory's centre
  // (tool_parameters of them: 10, and the offsets), 0 when that is the model.
  double lowest_self_clearance = 0.0;
  std::string self_pair;
  double tool_condition_number = 0.0;
  int tool_parameters = 0;
};

// InputError: min_height that no trajectory satisfies (naming --min-height),
// a zero gravity.
ExcitationSummary design_excitation(const Model& model, const BaseParameters& base,
                                    const ExcitationOptions& options);

// Writes a trajectory CSV: t, the joint columns (those above the sensor link
// first, the held ones at their positions), JOINT_vel, JOINT_acc (0 for a
// held joint), gx,gy,gz (not for a wrist: gravity then follows from the
// upstream joints), and block when the samples have blocks.
void write_trajectory(const std::string& path, const Model& model, const Samples& trajectory);

}  // namespace massid

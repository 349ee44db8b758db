// Experiment design: choose the static poses (joint positions and platform
// tilts) that determine the base parameters as well as the platform allows
// (paper eqs. 34-36 and sec. V).
//
// Options -> design() -> DesignSummary; evaluate_plan() gives the same figures
// for an existing plan.
//
// Criteria (minimised):
//   cond   the paper's eq. 36 number: condition number of the stacked moment
//          rows over the moment unknowns (all but M and the force offsets),
//          unscaled, in the reported basis (the default);
//   d-opt  -log det of the information matrix A^T W A over all unknowns, rows
//          weighted by 1/sigma^2 of their axis (D-optimality: independent of
//          the basis and of the units).
// Optimiser: greedy D-optimal start from random feasible candidates, then
// Fedorov exchange against the candidates (DETMAX style) and a pattern-search
// refinement of each pose's joints and tilt (or of the shared tilt groups),
// alternated until no gain.
// Deterministic for a given seed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/gravity.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"

namespace massid {

enum class Criterion { Cond, DOpt };

// `count` tilts evenly spread on the rim of the cone of half-angle tilt_max
// (rad) around level: where design's tilt groups start, and the blocks of
// design --dynamic --tilt-max.
std::vector<Tilt> cone_tilts(const Eigen::Vector3d& level, double tilt_max, int count);

inline constexpr double kDefaultMinHeight = 0.05;  // m
// m: the default distance between the centre lines of two arm links that no
// single link joins (a wrist: DesignOptions, ExcitationOptions::self_clearance).
inline constexpr double kDefaultSelfClearance = 0.05;

struct DesignOptions {
  int poses = 30;
  std::optional<double> tilt_max;  // rad: any tilt within this cone around level
  int tilt_groups = 0;             // with tilt_max: this many shared tilts (0: one per pose)
  std::vector<Tilt> tilts;         // or only these (empty and no tilt_max: level only)
  Eigen::Vector3d level_gravity{0.0, 0.0, -kStandardGravity};  // sensor frame, platform level
  std::map<std::string, std::pair<double, double>> limits;     // joint -> narrowed range
  // Fraction of each limited joint's URDF range kept free at each end (as
  // design --dynamic's ExcitationLimits::position_margin): a real arm hits
  // itself near its limits. `limits` narrow the range further.
  double position_margin = 0.1;
  // m: every point that moves with the joints (link origins, centres of mass,
  // the bounding spheres of primitive collision shapes) stays this far above
  // the platform plane: the plane through the sensor-frame origin normal to
  // level gravity (the mounting plate). Default 5 cm; nullopt: no constraint.
  std::optional<double> min_height = kDefaultMinHeight;
  // false: when no pose satisfies min_height (a sensor link below the mount,
  // say), design goes on without it and says so (DesignSummary::
  // min_height_relaxed); true (the CLI's explicit --min-height): InputError.
  bool min_height_required = false;
  // Poses kept level when level and other tilts are allowed (a cone, or a
  // list with 0:0): fz then varies by M g (1 - cos tilt), which separates the
  // total mass from the fz offset and checks the plan where the robot works.
  // -1: automatic, a quarter of the poses (at least 1 of 2 or more); 0: none
  // (the optimiser chooses every tilt).
  int level_poses = -1;
  Criterion criterion = Criterion::Cond;
  double noise_force = 0.05;    // N, per axis: for the predicted standard deviations
  double noise_moment = 0.005;  // N m
  std::uint64_t seed = 1;
  int candidates = 0;  // random feasible candidate poses; 0: automatic
  // A wrist (a sensor link below movable joints, Model::upstream_joints): the
  // poses move the arm's joints too (within their limits less 10 % of the
  // range at each end, `limits` narrowing them as the others), gravity in the
  // sensor frame follows from them and `root_gravity` (URDF root frame; no
  // tilts, level_gravity unused), min_height is the height above the floor
  // and self_clearance the arm's distance from itself, as for design
  // --dynamic (excitation.hpp).
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
  std::optional<double> self_clearance = kDefaultSelfClearance;
  // false: the arm above a wrist sensor is held still wherever it is, the
  // poses move the joints below it with gravity from level_gravity and the
  // tilts (as for a sensor link at the root).
  bool move_arm = true;
};

struct PlanPose {
  Eigen::VectorXd q;  // [num_joints]
  Tilt tilt;
  int group = -1;              // index of a shared tilt (listed or tilt group), -1: its own
  bool level = false;          // one of the poses kept level (DesignOptions::level_poses)
  Eigen::Vector3d gravity;     // sensor frame
  Eigen::VectorXd q_upstream;  // a wrist: the arm's joints [num_upstream_joints]; else empty
};

struct DesignSummary {
  std::vector<PlanPose> plan;     // in the order to run it
  double condition_number = 0.0;  // eq. 36 (as identify reports it)
  double log_det = 0.0;           // log det(A^T W A), all unknowns
  bool identifiable = false;      // full rank over every unknown
  Eigen::VectorXd predicted_std;  // [num_unknowns] at the given noise
  Wrench expected_error;          // RMS predicted-wrench error per axis over random feasible poses
  int tilt_changes = 0;           // distinct consecutive tilts - 1 (0 for a wrist: no tilts)
  double joint_travel = 0.0;      // sum of |dq| along the order (rad or m; a wrist: the arm too)
  double seconds = 0.0;           // optimisation time
  std::string identifiability_message;  // when !identifiable
  int level_poses = 0;                  // poses kept level (DesignOptions::level_poses)
  bool min_height_relaxed = false;      // min_height dropped: no pose satisfies it
  // Lowest clearance over the plan of the checked points above the platform
  // plane (m, as for DesignOptions::min_height; +inf when nothing moves), its
  // link, and how many links have collision meshes (checked at their origin
  // and centre of mass only).
  double lowest_clearance = 0.0;
  std::string lowest_link;
  int links_with_meshes = 0;
};

// Throws InputError for options that contradict the model (unknown joints,
// empty ranges, no feasible pose).
DesignSummary design(const Model& model, const BaseParameters& base, const DesignOptions& options);

// The same figures for an existing plan or data file. Options give the noise,
// the level gravity and the constraints of the random poses for expected_error.
DesignSummary evaluate_plan(const Model& model, const BaseParameters& base, const Samples& plan,
                            const DesignOptions& options);

// The lowest clearance above the platform plane over the rows of `samples`
// of the points options.min_height constrains (those that move with the
// joints; options.level_gravity sets "up"): height (m; +inf when nothing
// moves), its row and link.
struct Clearance {
  double height = 0.0;
  int row = -1;
  std::string link;
};
Clearance lowest_clearance(const Model& model, const DesignOptions& options,
                           const Samples& samples);

// Joints held still (the CLI's --fixed) are fixed in the model given to
// design: see hold_joints() in model.hpp.

// Writes a plan CSV: the joint columns (held joints too, at their positions),
// gx,gy,gz, tilt_x_deg, tilt_y_deg.
void write_plan(const std::string& path, const Model& model, const std::vector<PlanPose>& plan);

}  // namespace massid

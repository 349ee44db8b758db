// Experiment design: the paper's targets (eq. 36 computed with the paper's own
// W, independently of the design code), constraints, determinism, and the
// predicted standard deviations against the errors of real identifications.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "massid/base_parameters.hpp"
#include "massid/design.hpp"
#include "massid/estimation.hpp"
#include "massid/kinematics.hpp"
#include "massid/regressor.hpp"
#include "massid/simulate.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Samples as_samples(const std::vector<PlanPose>& plan) {
  Samples s;
  s.source = "plan";
  s.q.resize(plan.size(), plan.front().q.size());
  s.gravity.resize(plan.size(), 3);
  for (size_t i = 0; i < plan.size(); ++i) {
    s.q.row(i) = plan[i].q.transpose();
    s.gravity.row(i) = plan[i].gravity.transpose();
  }
  return s;
}

DesignOptions puma_options() {
  DesignOptions o;
  o.poses = 30;
  o.level_gravity = Eigen::Vector3d(0, 0, kStandardGravity);  // the paper's sensor frame: +z down
  return o;
}

class PumaDesign : public ::testing::Test {
 protected:
  Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  BaseParameters base = find_base_parameters(model);
};

TEST_F(PumaDesign, PapersConstraintsBeatThePapersTenPointEight) {
  DesignOptions o = puma_options();
  o.tilts = {{0, 0}, {0, 25 * kDeg}};
  const DesignSummary d = design(model, base, o);
  ASSERT_EQ(d.plan.size(), 30u);
  const double paper = test::paper_condition_number(as_samples(d.plan));
  EXPECT_LE(paper, 4.8);  // the paper: 10.8; about 4.62 is reachable
  EXPECT_NEAR(d.condition_number, paper, 1e-9 * paper);
  // Level and tilted poses grouped: one tilt change.
  EXPECT_EQ(d.tilt_changes, 1);
  for (const PlanPose& p : d.plan) {
    EXPECT_EQ(p.tilt.x, 0.0);
    EXPECT_TRUE(p.tilt.y == 0.0 || std::abs(p.tilt.y - 25 * kDeg) < 1e-15);
  }
}

TEST_F(PumaDesign, AnyTiltUpTo25DegreesReaches2Point5) {
  DesignOptions o = puma_options();
  o.tilt_max = 25 * kDeg;
  const DesignSummary d = design(model, base, o);
  EXPECT_LE(test::paper_condition_number(as_samples(d.plan)), 2.5);  // about 2.26 is reachable
  for (const PlanPose& p : d.plan)
    EXPECT_LE(tilt_angle(o.level_gravity, p.tilt), 25 * kDeg + 1e-12);
}

TEST_F(PumaDesign, FourTiltGroupsKeepTheTargetWithThreeTiltChanges) {
  DesignOptions o = puma_options();
  o.tilt_max = 25 * kDeg;
  o.tilt_groups = 4;
  const DesignSummary d = design(model, base, o);
  EXPECT_LE(test::paper_condition_number(as_samples(d.plan)), 2.5);
  EXPECT_LE(d.tilt_changes, 3);
  for (const PlanPose& p : d.plan)
    EXPECT_LE(tilt_angle(o.level_gravity, p.tilt), 25 * kDeg + 1e-12);
}

TEST_F(PumaDesign, SameSeedSamePlanOtherSeedOtherPlan) {
  DesignOptions o = puma_options();
  o.tilts = {{0, 0}, {0, 25 * kDeg}};
  o.poses = 12;
  o.candidates = 300;
  const DesignSummary a = design(model, base, o), b = design(model, base, o);
  o.seed = 2;
  const DesignSummary c = design(model, base, o);
  ASSERT_EQ(a.plan.size(), b.plan.size());
  bool differs = false;
  for (size_t i = 0; i < a.plan.size(); ++i) {
    EXPECT_EQ(a.plan[i].q, b.plan[i].q);
    EXPECT_EQ(a.plan[i].gravity, b.plan[i].gravity);
    differs = differs || a.plan[i].q != c.plan[i].q;
  }
  EXPECT_TRUE(differs);
}

// design -> simulate -> identify: the errors match the standard deviations
// that design predicted, over 200 noise seeds.
TEST_F(PumaDesign, PredictedStandardDeviationsMatchIdentifiedErrors) {
  DesignOptions o = puma_options();
  o.tilt_max = 25 * kDeg;
  o.noise_force = 0.05;
  o.noise_moment = 0.004;
  const DesignSummary d = design(model, base, o);
  Samples s = as_samples(d.plan);
  const Eigen::VectorXd truth = base.K * nominal_standard_parameters(model);
  Eigen::VectorXd sum_z2 = Eigen::VectorXd::Zero(base.num_unknowns());
  IdentifyOptions known;
  known.sigma_force = o.noise_force;
  known.sigma_moment = o.noise_moment;
  const int seeds = 200;
  for (int seed = 1; seed <= seeds; ++seed) {
    SimulateOptions so;
    so.noise_force = o.noise_force;
    so.noise_moment = o.noise_moment;
    so.seed = seed;
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary r = identify(model, base, s, known);
    if (seed == 1) {
      EXPECT_LT((r.stddev - d.predicted_std).norm(), 1e-9 * d.predicted_std.norm());
    }
    sum_z2 += ((r.value - truth).cwiseQuotient(d.predicted_std)).cwiseAbs2();
  }
  for (int i = 0; i < base.num_unknowns(); ++i) {
    const double spread = std::sqrt(sum_z2[i] / seeds);
    EXPECT_GT(spread, 0.8) << base.unknown_name(i);
    EXPECT_LT(spread, 1.25) << base.unknown_name(i);
  }
}

TEST_F(PumaDesign, OffsetsNeedAThirdGravityDirection) {
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters with_offset = find_base_parameters(model, bo);
  DesignOptions o = puma_options();
  o.poses = 16;
  o.candidates = 400;
  o.tilts = {{0, 0}, {0, 25 * kDeg}};
  EXPECT_FALSE(design(model, with_offset, o).identifiable);
  o.tilts = {{0, 0}, {0, 25 * kDeg}, {25 * kDeg, 0}};
  const DesignSummary d = design(model, with_offset, o);
  EXPECT_TRUE(d.identifiable);
  EXPECT_EQ(d.predicted_std.size(), 16);
}

TEST_F(PumaDesign, EvaluateGivesIdentifysConditionNumber) {
  Samples plan = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  DesignOptions o = puma_options();
  const DesignSummary e = evaluate_plan(model, base, plan, o);
  plan.wrench = simulate_wrenches(model, plan);
  EXPECT_NEAR(e.condition_number, identify(model, base, plan).condition_number, 1e-12);
  EXPECT_NEAR(e.condition_number, test::paper_condition_number(plan), 1e-9);
  EXPECT_EQ(e.tilt_changes, 1);
}

TEST(Design, HeldJointsNarrowedRangesAndMinimumHeight) {
  // The wrist held still as in the paper: the base parameters are those such an
  // experiment can determine, and the plan holds the joint at its position.
  const Model full = load_urdf(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  const Model model = hold_joints(full, {{"wrist_3_joint", 0.4}});
  ASSERT_EQ(model.num_joints(), 5);
  const BaseParameters base = find_base_parameters(model);
  EXPECT_LT(base.num_mass(), find_base_parameters(full).num_mass());
  DesignOptions o;
  o.poses = 24;
  o.candidates = 500;
  o.tilt_max = 20 * kDeg;
  o.limits["shoulder_pan_joint"] = {-1.0, 1.0};
  o.min_height = 0.05;
  const DesignSummary d = design(model, base, o);
  EXPECT_TRUE(d.identifiable);
  const int pan = model.find_joint("shoulder_pan_joint");
  KinematicsData kin(model);
  for (const PlanPose& p : d.plan) {
    EXPECT_GE(p.q[pan], -1.0);
    EXPECT_LE(p.q[pan], 1.0);
    for (int j = 0; j < model.num_joints(); ++j) {
      EXPECT_GE(p.q[j], model.joints[j].lower);
      EXPECT_LE(p.q[j], model.joints[j].upper);
    }
    forward_kinematics(model, kin, p.q);
    for (int l = 0; l < model.num_links(); ++l) {
      // Links fixed to the mount (sensor, plate, base, shoulder origin) do not move.
      if (model.links[l].name == "sensor" || model.links[l].name == "plate" ||
          model.links[l].name == "base_link" || model.links[l].name == "shoulder_link")
        continue;
      EXPECT_GE(kin.position[l].z(), 0.05 - 1e-12) << model.links[l].name;
    }
  }
}

TEST(Design, DOptimalityMaximisesTheLogDeterminant) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/branching/branching.urdf");
  const BaseParameters base = find_base_parameters(model);
  DesignOptions o;
  o.poses = 30;
  o.candidates = 600;
  o.tilt_max = 20 * kDeg;
  const DesignSummary cond = design(model, base, o);
  o.criterion = Criterion::DOpt;
  const DesignSummary dopt = design(model, base, o);
  EXPECT_TRUE(dopt.identifiable);
  EXPECT_GT(dopt.log_det, cond.log_det);
  EXPECT_LT(cond.condition_number, dopt.condition_number);
}

TEST(Design, NoiseScalesThePredictedDeviations) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/wrist_tool/wrist_tool.urdf");
  const BaseParameters base = find_base_parameters(model);
  DesignOptions o;
  o.poses = 10;
  o.tilt_max = 80 * kDeg;
  const DesignSummary a = design(model, base, o);
  const Samples plan = as_samples(a.plan);
  o.noise_force *= 2;
  o.noise_moment *= 2;
  const DesignSummary b = evaluate_plan(model, base, plan, o);
  EXPECT_LT((b.predicted_std - 2 * a.predicted_std).norm(), 1e-9 * a.predicted_std.norm());
  EXPECT_LT((b.expected_error - 2 * a.expected_error).norm(), 1e-9 * a.expected_error.norm());
}

}  // namespace
}  // namespace massid

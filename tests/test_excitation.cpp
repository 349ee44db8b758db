// The exciting-trajectory designer (excitation.hpp design_excitation): the
// limits hold at every written sample and the trajectory is at rest at both
// ends (checked on the samples, derivatives against finite differences of the
// positions); the optimised condition number beats random Fourier
// trajectories scaled to the same limits (computed here with the SVD of the
// stacked regressor, not the designer's criterion code); d-opt raises log det;
// the predicted std match the spread of the estimates over noise seeds.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kLevel;

Model ur_like() {
  return load_urdf(std::string(MASSID_SOURCE_DIR) + "/examples/ur_like/ur_like.urdf");
}

BaseParameters level_base(const Model& model) {
  BaseParameterOptions bo;
  bo.layout = ParameterLayout::full();
  bo.fixed_gravity = true;
  bo.sensor_gravity = kLevel;
  return find_base_parameters(model, bo);
}

// A cheap design: 10 s, 3 harmonics, 100 Hz.
ExcitationOptions cheap() {
  ExcitationOptions o;
  o.duration = 10.0;
  o.period = 10.0;
  o.harmonics = 3;
  o.rate = 100.0;
  o.evaluations = 400;
  o.random_baseline = 0;
  return o;
}

// The condition number of the column-scaled, noise-weighted stacked
// regressor of the samples (SVD: estimation.hpp), independent of the
// designer's criterion code.
double svd_condition(const Model& model, const BaseParameters& base, const Samples& s,
                     const ExcitationOptions& o) {
  Eigen::MatrixXd A = stacked_regressor(model, base, s);
  for (Eigen::Index r = 0; r < A.rows(); ++r)
    A.row(r) /= r % 6 < 3 ? o.noise_force : o.noise_moment;
  return scaled_condition_number(A);
}

double log_det(const Model& model, const BaseParameters& base, const Samples& s,
               const ExcitationOptions& o) {
  Eigen::MatrixXd A = stacked_regressor(model, base, s);
  for (Eigen::Index r = 0; r < A.rows(); ++r)
    A.row(r) /= r % 6 < 3 ? o.noise_force : o.noise_moment;
  const Eigen::LLT<Eigen::MatrixXd> llt(A.transpose() * A);
  return 2.0 * llt.matrixLLT().diagonal().array().log().sum();
}

// Lowest height above the plane through the sensor origin (normal to level
// gravity) of every moving link origin over the samples.
double lowest_moving_origin(const Model& model, const Samples& s) {
  KinematicsData kin(model), ref(model);
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.num_joints()), q1 = q0;
  q1.setConstant(1.0);
  forward_kinematics(model, ref, q0);
  forward_kinematics(model, kin, q1);
  std::vector<int> moving;
  for (int l = 0; l < model.num_links(); ++l)
    if ((kin.position[l] - ref.position[l]).norm() > 1e-9) moving.push_back(l);
  double lowest = INFINITY;
  for (int i = 0; i < s.size(); ++i) {
    forward_kinematics(model, kin, s.q.row(i).transpose());
    for (int l : moving) lowest = std::min(lowest, kin.position[l].z());
  }
  return lowest;
}

TEST(Excitation, EveryWrittenSampleWithinTheLimitsAndAtRestAtBothEnds) {
  Model model = ur_like();
  model.joints[0].velocity_limit = 0.4;  // as --velocity-limit does
  ExcitationOptions o = cheap();
  o.limits.joint_acceleration.assign(model.num_joints(), 0.0);
  o.limits.joint_acceleration[2] = 1.5;
  o.min_height = 0.1;
  o.min_height_required = true;
  const BaseParameters base = level_base(model);
  const ExcitationSummary d = design_excitation(model, base, o);
  const Samples& s = d.samples;
  ASSERT_EQ(s.size(), 1001);
  const double dt = 1.0 / o.rate;
  double used = 0.0;  // the largest fraction of a velocity or acceleration limit used
  for (int j = 0; j < model.num_joints(); ++j) {
    const Joint& joint = model.joints[j];
    const double margin = o.limits.position_margin * (joint.upper - joint.lower);
    const double v = j == 0 ? 0.4 : joint.velocity_limit > 0 ? joint.velocity_limit : 1.0;
    const double a = j == 2 ? 1.5 : 4.0;
    double vmax = 0.0, amax = 0.0;
    for (int i = 0; i < s.size(); ++i) {
      if (joint.limited) {
        EXPECT_GE(s.q(i, j), joint.lower + margin - 1e-12) << joint.name << " row " << i;
        EXPECT_LE(s.q(i, j), joint.upper - margin + 1e-12) << joint.name << " row " << i;
      }
      vmax = std::max(vmax, std::abs(s.qd(i, j)));
      amax = std::max(amax, std::abs(s.qdd(i, j)));
      // The written velocity is the positions' derivative (central differences).
      if (i > 0 && i + 1 < s.size()) {
        EXPECT_NEAR((s.q(i + 1, j) - s.q(i - 1, j)) / (2 * dt), s.qd(i, j), 1e-3 * (v + 1))
            << joint.name << " row " << i;
      }
    }
    EXPECT_LE(vmax, v * (1 + 1e-12)) << joint.name;
    EXPECT_LE(amax, a * (1 + 1e-12)) << joint.name;
    used = std::max({used, vmax / v, amax / a});
    for (const int i : {0, s.size() - 1}) {
      EXPECT_NEAR(s.qd(i, j), 0.0, 1e-9) << joint.name << " row " << i;
      EXPECT_NEAR(s.qdd(i, j), 0.0, 1e-9) << joint.name << " row " << i;
    }
  }
  EXPECT_GT(used, 0.5) << "a timid trajectory: the limits do not bind";
  EXPECT_TRUE(d.at_rest_at_end);
  EXPECT_GE(lowest_moving_origin(model, s), 0.1 - 1e-12);
  EXPECT_GE(d.lowest_clearance, 0.1 - 1e-12);
  // The same for the seed: identical samples.
  const ExcitationSummary again = design_excitation(model, base, o);
  EXPECT_EQ(again.samples.q, s.q);
  EXPECT_EQ(again.samples.qdd, s.qdd);
}

TEST(Excitation, OptimisedConditionNumberThreeTimesBetterThanRandom) {
  const Model model = ur_like();
  const BaseParameters base = level_base(model);
  ExcitationOptions o = cheap();
  o.harmonics = 5;
  o.rate = 20.0;
  o.evaluations = 1500;
  const ExcitationSummary d = design_excitation(model, base, o);
  const double optimised = svd_condition(model, base, d.samples, o);
  EXPECT_NEAR(optimised, d.condition_number, 1e-6 * optimised);
  // Random Fourier trajectories scaled to the same limits, 20 seeds.
  std::vector<double> random;
  for (std::uint64_t seed = 100; seed < 120; ++seed)
    random.push_back(svd_condition(
        model, base,
        sample_trajectory(random_fourier_trajectory(model, o.harmonics, o.period, seed, o.limits),
                          o.duration, o.rate, kLevel),
        o));
  std::nth_element(random.begin(), random.begin() + 10, random.end());
  EXPECT_LT(3.0 * optimised, random[10]) << "optimised " << optimised;
}

TEST(Excitation, DOptimalityRaisesTheLogDeterminant) {
  const Model model = ur_like();
  const BaseParameters base = level_base(model);
  ExcitationOptions o = cheap();
  o.criterion = Criterion::DOpt;
  o.evaluations = 0;  // the best random start
  const ExcitationSummary start = design_excitation(model, base, o);
  o.evaluations = 600;
  const ExcitationSummary d = design_excitation(model, base, o);
  const double before = log_det(model, base, start.samples, o);
  const double after = log_det(model, base, d.samples, o);
  EXPECT_NEAR(after, d.log_det, 1e-6 * std::abs(after));
  // e^5: the confidence ellipsoid's volume shrinks by a factor of ~150.
  EXPECT_GT(after, before + 5.0) << before << " -> " << after;
}

TEST(Excitation, MinHeightNoTrajectoryCanKeepIsAnInputErrorNamingTheOption) {
  const Model model = ur_like();
  ExcitationOptions o = cheap();
  o.evaluations = 50;
  o.min_height = 5.0;  // above the arm's reach
  o.min_height_required = true;
  try {
    design_excitation(model, level_base(model), o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lower the clearance"), std::string::npos) << e.what();
    // The hints name the clearance setting (the CLI spells it --min-height).
    ASSERT_FALSE(e.hints().empty());
    EXPECT_EQ(e.hints().front().setting, Hint::Setting::MinHeight);
  }
}

// Monte Carlo: the designed trajectory simulated with noise 100 times and
// identified each time; the spread of each base parameter about its true
// value agrees with the std design predicted within 20 %.
TEST(Excitation, PredictedStdMatchTheSpreadOverHundredNoiseSeeds) {
  const Model model = load_urdf(test::examples()[0].urdf);  // puma260
  const BaseParameters base = level_base(model);
  ExcitationOptions o = cheap();
  o.rate = 50.0;
  o.evaluations = 200;
  o.min_height.reset();
  const ExcitationSummary d = design_excitation(model, base, o);
  Samples s = d.samples;
  const Eigen::VectorXd truth = base.K * ParameterLayout::full().nominal(model);
  const int seeds = 100, p = base.num_mass();
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(p);
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = o.noise_force;
  so.noise_moment = o.noise_moment;
  for (int seed = 1; seed <= seeds; ++seed) {
    so.seed = static_cast<std::uint64_t>(seed);
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary fit = identify(model, base, s);
    sum_sq += (fit.value.head(p) - truth).cwiseAbs2();
  }
  for (int i = 0; i < p; ++i) {
    const double spread = std::sqrt(sum_sq[i] / seeds);
    EXPECT_NEAR(spread / d.predicted_std[i], 1.0, 0.2) << base.params[i].name;
  }
}

}  // namespace
}  // namespace massid

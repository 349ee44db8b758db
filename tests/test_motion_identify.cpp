// Identification in motion, end to end through the library: an exciting
// trajectory (excitation.hpp), the wrench the URDF's inertials produce along it
// (simulate_wrenches, dynamic) with sensor noise and a constant offset, the
// dynamic base parameters identified (identify), compared with their true
// values K pi_URDF, and the fit used to predict the wrench along another
// trajectory. The truth is independent of the estimator: K and pi come from
// the URDF alone; the regressor itself is checked against finite differences
// and MuJoCo in test_motion_regressor.cpp and test_mujoco_motion.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kLevel;
const Wrench kDynamicOffset = (Wrench() << 2.0, -1.0, 3.0, 0.2, -0.1, 0.05).finished();

// The base parameters' true values: K pi for the URDF's ten parameters per link.
Eigen::VectorXd truth(const Model& model, const BaseParameters& base) {
  return base.K * ParameterLayout::full().nominal(model);
}

Samples log_of(const Model& model, const FourierTrajectory& tr, double duration, double rate,
               const Eigen::Vector3d& g, std::uint64_t seed, bool offset = true) {
  Samples s = sample_trajectory(tr, duration, rate, g);
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  so.seed = seed;
  if (offset) so.offset = kDynamicOffset;
  s.wrench = simulate_wrenches(model, s, so);
  return s;
}

// Largest |estimate - truth| / std over the base parameters (offsets excluded).
double worst_normalised_error(const BaseParameters& base, const IdentifySummary& fit,
                              const Eigen::VectorXd& t) {
  double worst = 0.0;
  for (int i = 0; i < base.num_mass(); ++i)
    worst = std::max(worst, std::abs(fit.value[i] - t[i]) / fit.stddev[i]);
  return worst;
}

// Per-axis largest prediction error as a fraction of the axis' range.
Eigen::Matrix<double, 6, 1> prediction_error(const Model& model, const BaseParameters& base,
                                             const IdentifySummary& fit, const Samples& s) {
  RegressorData data(model, base);
  Eigen::MatrixXd P(s.size(), 6);
  for (int i = 0; i < s.size(); ++i) {
    base_regressor(model, base, data, s, i);
    P.row(i) = (data.base * fit.value).transpose();
  }
  Eigen::Matrix<double, 6, 1> e;
  for (int k = 0; k < 6; ++k) {
    const double range = s.wrench.col(k).maxCoeff() - s.wrench.col(k).minCoeff();
    e[k] = (P.col(k) - s.wrench.col(k)).cwiseAbs().maxCoeff() / range;
  }
  return e;
}

// The fit's prediction error along another trajectory (exact velocities,
// noise-free wrench, no offset), per axis as a fraction of its range. The
// identified offsets hold what level data cannot tell from them (the total
// mass in fz ...): the mechanism's part is the fit less the true offset.
Eigen::Matrix<double, 6, 1> error_on_another_trajectory(const Model& model,
                                                        const BaseParameters& base,
                                                        const IdentifySummary& fit) {
  Samples check =
      sample_trajectory(random_fourier_trajectory(model, 4, 7.0, 99), 14.0, 200.0, kLevel);
  SimulateOptions exact;
  exact.dynamic = true;
  check.wrench = simulate_wrenches(model, check, exact);
  IdentifySummary mechanism = fit;
  mechanism.value.tail(6) -= kDynamicOffset;
  return prediction_error(model, base, mechanism, check);
}

TEST(MotionIdentify, BaseParametersWithinFourStdAndPredictionWithinOnePercent) {
  for (const test::Example& ex : test::examples()) {
    const Model model = load_urdf(ex.urdf);
    if (model.num_joints() == 0) continue;  // wrist_tool: below (sensor in motion)
    SCOPED_TRACE(ex.name);
    const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 11);
    const Samples s = log_of(model, tr, 30.0, 1000.0, kLevel, 1);
    const BaseParameters base = find_base_parameters(model, motion_base_options(s, true));
    EXPECT_TRUE(base.fixed_gravity);
    const IdentifySummary fit = identify(model, base, s);
    EXPECT_LT(worst_normalised_error(base, fit, truth(model, base)), 4.0);
    EXPECT_NEAR(fit.sigma[0], 0.1, 0.01);
    EXPECT_NEAR(fit.sigma[3], 0.01, 0.001);
    // Another trajectory: the fit predicts it within 1 % of each axis' range.
    EXPECT_LT(error_on_another_trajectory(model, base, fit).maxCoeff(), 0.01);
  }
}

TEST(MotionIdentify, TiltedGravityDeterminesTheTotalMassWithOffsets) {
  const Model model = load_urdf(test::examples()[1].urdf);  // ur_like
  const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 3);
  // Three platform tilts, one after the other (gravity constant within each).
  Samples s = log_of(model, tr, 30.0, 500.0, kLevel, 2);
  const Eigen::Vector3d tilts[3] = {kLevel,
                                    Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) * kLevel,
                                    Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * kLevel};
  for (int i = 0; i < s.size(); ++i) s.gravity.row(i) = tilts[3 * i / s.size()].transpose();
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  so.offset = kDynamicOffset;
  s.wrench = simulate_wrenches(model, s, so);
  const BaseParameters base = find_base_parameters(model, motion_base_options(s, true));
  EXPECT_FALSE(base.fixed_gravity);
  ASSERT_GE(base.total_mass, 0);
  EXPECT_EQ(base.num_mass(), 44);
  const IdentifySummary fit = identify(model, base, s);
  const Eigen::VectorXd t = truth(model, base);
  EXPECT_LT(worst_normalised_error(base, fit, t), 4.0);
  EXPECT_NEAR(fit.value[base.total_mass], model.nominal_total_mass(),
              4 * fit.stddev[base.total_mass]);
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(fit.value[base.num_mass() + k], so.offset[k], 4 * fit.stddev[base.num_mass() + k]);
}

// A wrench in the reaction convention (MuJoCo's sensor, some drivers) negates
// every parameter: in motion the set-up checks cannot compare each row's force
// with gravity, so the fit's total mass is the evidence. The request refuses
// it (wrench-sign, the fix named) for the log negated, level without offsets
// and tilted three ways with offsets (level with offsets, the total mass is not
// identifiable), and takes the log as recorded; with the checks off the fit
// shows what was refused: the URDF's total mass negated.
TEST(MotionIdentify, NegatedWrenchInMotionIsRefusedByTheFittedTotalMass) {
  const Model model = load_urdf(test::examples()[1].urdf);  // ur_like
  const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 5);
  for (const bool offset : {false, true}) {
    SCOPED_TRACE(offset ? "tilted, with offsets" : "level, without offsets");
    Samples recorded = sample_trajectory(tr, 20.0, 500.0, kLevel);
    const Eigen::Vector3d tilts[3] = {kLevel,
                                      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) * kLevel,
                                      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * kLevel};
    if (offset)  // three platform tilts, one after the other
      for (int i = 0; i < recorded.size(); ++i)
        recorded.gravity.row(i) = tilts[3 * i / recorded.size()].transpose();
    SimulateOptions so;
    so.dynamic = true;
    so.noise_force = 0.1;
    so.noise_moment = 0.01;
    if (offset) so.offset = kDynamicOffset;
    recorded.wrench = simulate_wrenches(model, recorded, so);
    Samples negated = recorded;
    negated.wrench = -recorded.wrench;
    IdentifyRequest request;
    request.dynamic = true;
    request.offset = offset;
    const Identification good = identify(model, request, IdentifySource::data(recorded));
    ASSERT_GE(good.base.total_mass, 0);
    EXPECT_NEAR(good.summary.value[good.base.total_mass], model.nominal_total_mass(),
                4 * good.summary.stddev[good.base.total_mass]);
    try {
      identify(model, request, IdentifySource::data(negated));
      ADD_FAILURE() << "a negated wrench in motion was identified";
    } catch (const SetupRefused& e) {
      ASSERT_EQ(e.errors().size(), 1u);
      EXPECT_EQ(e.errors()[0].code, "wrench-sign");
      EXPECT_NE(std::string(e.what()).find("negate fx,fy,fz,mx,my,mz"), std::string::npos);
    }
    request.checks = false;
    const Identification unchecked = identify(model, request, IdentifySource::data(negated));
    EXPECT_NEAR(unchecked.summary.value[unchecked.base.total_mass], -model.nominal_total_mass(),
                4 * unchecked.summary.stddev[unchecked.base.total_mass]);
  }
}

// The reported standard deviations against the spread of the estimates over
// 100 noise seeds (same trajectory): within a factor 1.5.
TEST(MotionIdentify, ReportedStdMatchTheSpreadOverSeeds) {
  const Model model = load_urdf(test::examples()[0].urdf);  // puma260
  const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 11);
  Samples s = log_of(model, tr, 30.0, 100.0, kLevel, 0);
  const BaseParameters base = find_base_parameters(model, motion_base_options(s, true));
  const Eigen::VectorXd t = truth(model, base);
  const int seeds = 100, p = base.num_mass();
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(p), reported = Eigen::VectorXd::Zero(p);
  for (int seed = 1; seed <= seeds; ++seed) {
    SimulateOptions so;
    so.dynamic = true;
    so.noise_force = 0.1;
    so.noise_moment = 0.01;
    so.seed = static_cast<std::uint64_t>(seed);
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary fit = identify(model, base, s);
    for (int i = 0; i < p; ++i) {
      sum_sq[i] += (fit.value[i] - t[i]) * (fit.value[i] - t[i]);
      reported[i] += fit.stddev[i] / seeds;
    }
  }
  for (int i = 0; i < p; ++i) {
    const double spread = std::sqrt(sum_sq[i] / seeds);
    EXPECT_GT(reported[i] / spread, 1 / 1.5) << base.params[i].name;
    EXPECT_LT(reported[i] / spread, 1.5) << base.params[i].name;
  }
}

// Velocities and accelerations derived from noisy positions (encoder-level
// noise) with the wrench filtered alike: within 4 std, prediction within 2 %.
TEST(MotionIdentify, DerivativesFromPositionsStayWithinFourStd) {
  for (const test::Example& ex : test::examples()) {
    const Model model = load_urdf(ex.urdf);
    if (model.num_joints() == 0) continue;
    SCOPED_TRACE(ex.name);
    const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 21);
    Samples s = log_of(model, tr, 30.0, 1000.0, kLevel, 4);
    std::mt19937_64 rng(8);
    std::normal_distribution<double> encoder(0.0, 1e-5);  // rad: a 19-bit encoder
    for (int i = 0; i < s.size(); ++i)
      for (int j = 0; j < model.num_joints(); ++j) s.q(i, j) += encoder(rng);
    Samples raw = s;
    raw.qd.resize(s.size(), 0);
    raw.qdd.resize(s.size(), 0);
    MotionDataReport report;
    const Samples f = prepare_motion_samples(model, raw, {}, &report);
    EXPECT_TRUE(report.derived);
    EXPECT_TRUE(f.derivatives_filtered);
    const BaseParameters base = find_base_parameters(model, motion_base_options(f, true));
    const IdentifySummary fit = identify(model, base, f);
    EXPECT_LT(worst_normalised_error(base, fit, truth(model, base)), 4.0);
    EXPECT_LT(error_on_another_trajectory(model, base, fit).maxCoeff(), 0.02);
  }
}

// A tool on a wrist sensor: the arm's joints above the sensor give its
// motion and gravity; all ten parameters of the tool (wrist_3_link and the
// tool fixed to it: one rigid body) are determined from the wrist wrench.
TEST(MotionIdentify, ToolOnAWristSensorFromTheArmJoints) {
  const std::string urdf = test::examples()[1].urdf;  // ur_like
  const Model arm = load_urdf(urdf);
  const Model wrist = load_urdf(urdf, "wrist_3_link");
  ASSERT_EQ(wrist.num_joints(), 0);
  ASSERT_EQ(wrist.num_upstream_joints(), 6);
  const FourierTrajectory tr = random_fourier_trajectory(arm, 5, 10.0, 5);
  const Samples arm_log = sample_trajectory(tr, 30.0, 500.0, kLevel);
  Samples s;
  s.source = "wrist";
  s.q.resize(arm_log.size(), 0);
  s.qd.resize(arm_log.size(), 0);
  s.qdd.resize(arm_log.size(), 0);
  s.q_upstream = arm_log.q;
  s.qd_upstream = arm_log.qd;
  s.qdd_upstream = arm_log.qdd;
  s.gravity.resize(arm_log.size(), 3);
  s.gravity_from_upstream = true;
  s.time = arm_log.time;
  s.line = arm_log.line;
  resolve_upstream(wrist, s);
  ASSERT_TRUE(s.has_sensor_motion());
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  s.wrench = simulate_wrenches(wrist, s, so);
  const BaseParameters base = find_base_parameters(wrist, motion_base_options(s, false));
  EXPECT_TRUE(base.sensor_moving);
  EXPECT_EQ(base.num_mass(), 10);
  const IdentifySummary fit = identify(wrist, base, s);
  EXPECT_LT(worst_normalised_error(base, fit, truth(wrist, base)), 4.0);
}

TEST(MotionIdentify, StillArmOnALevelPlatformSaysWhatMotionWouldHelp) {
  const Model model = load_urdf(test::examples()[1].urdf);
  FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 11);
  tr.a.row(5).setZero();  // wrist_3 never moves
  tr.b.row(5).setZero();
  const Samples s = log_of(model, tr, 10.0, 200.0, kLevel, 1);
  BaseParameterOptions o = motion_base_options(s, false);
  const BaseParameters base = find_base_parameters(model, o);
  try {
    identify(model, base, s);
    FAIL() << "expected an IdentifiabilityError";
  } catch (const IdentifiabilityError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("wrist_3_joint"), std::string::npos) << m;
    EXPECT_NE(m.find("faster"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace massid

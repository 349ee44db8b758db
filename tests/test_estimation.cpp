// Identification: exact recovery from noise-free data, standard deviations that
// match the actual errors over many noise seeds, the eq. 36 condition number
// against the paper's own W, and clear failures when the data cannot determine
// the parameters.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>

#include "massid/base_parameters.hpp"
#include "massid/errors.hpp"
#include "massid/estimation.hpp"
#include "massid/regressor.hpp"
#include "massid/simulate.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

const Wrench kOffset = (Wrench() << 0.5, -0.3, 1.0, 0.05, -0.02, 0.03).finished();

// Plans that determine the offsets too (three or more gravity directions).
std::string offset_plan(const test::Example& ex) {
  if (ex.name == "puma260") return MASSID_SOURCE_DIR "/examples/puma260/holdout.csv";
  return ex.plan;
}

Eigen::VectorXd truth(const Model& model, const BaseParameters& base, const Wrench& offset) {
  Eigen::VectorXd t(base.num_unknowns());
  t.head(base.num_mass()) = base.K * nominal_standard_parameters(model);
  if (base.offset) t.tail(6) = offset;
  return t;
}

struct Case {
  test::Example example;
  bool offset;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const auto& ex : test::examples()) {
    out.push_back({ex, false});
    out.push_back({ex, true});
  }
  return out;
}

class EstimationTest : public ::testing::TestWithParam<Case> {};

TEST_P(EstimationTest, RecoversEveryBaseParameterFromNoiseFreeData) {
  const auto& [ex, offset] = GetParam();
  const Model model = load_urdf(ex.urdf);
  BaseParameterOptions bo;
  bo.offset = offset;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, offset ? offset_plan(ex) : ex.plan);
  SimulateOptions so;
  if (offset) so.offset = kOffset;
  s.wrench = simulate_wrenches(model, s, so);
  const IdentifySummary r = identify(model, base, s);
  const Eigen::VectorXd t = truth(model, base, so.offset);
  for (int i = 0; i < base.num_unknowns(); ++i)
    EXPECT_LE(std::abs(r.value[i] - t[i]), 1e-9 * std::max(std::abs(t[i]), 1e-3))
        << base.unknown_name(i) << " = " << t[i];
  EXPECT_LT(r.residual_rms.maxCoeff(), 1e-10);
}

TEST_P(EstimationTest, StandardDeviationsMatchTheErrorsOver200Seeds) {
  const auto& [ex, offset] = GetParam();
  const Model model = load_urdf(ex.urdf);
  BaseParameterOptions bo;
  bo.offset = offset;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, offset ? offset_plan(ex) : ex.plan);
  const Eigen::VectorXd t = truth(model, base, offset ? kOffset : Wrench::Zero());
  const int seeds = 200;
  Eigen::VectorXd sum_z2 = Eigen::VectorXd::Zero(base.num_unknowns());
  for (int seed = 1; seed <= seeds; ++seed) {
    SimulateOptions so;
    so.noise_force = 0.05;
    so.noise_moment = 0.004;
    so.seed = seed;
    if (offset) so.offset = kOffset;
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary r = identify(model, base, s);
    sum_z2 += ((r.value - t).cwiseQuotient(r.stddev)).cwiseAbs2();
  }
  const Eigen::VectorXd spread = (sum_z2 / seeds).cwiseSqrt();
  const double overall = std::sqrt(sum_z2.sum() / (seeds * base.num_unknowns()));
  EXPECT_GT(overall, 0.8);
  EXPECT_LT(overall, 1.25);
  for (int i = 0; i < base.num_unknowns(); ++i) {
    EXPECT_GT(spread[i], 0.75) << base.unknown_name(i);
    EXPECT_LT(spread[i], 1.3) << base.unknown_name(i);
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, EstimationTest, ::testing::ValuesIn(cases()),
                         [](const auto& info) {
                           return info.param.example.name + (info.param.offset ? "_offset" : "");
                         });

TEST(Estimation, GravityFromTheMeasuredForceGivesTheSameResult) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/ur_like/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const IdentifySummary a = identify(model, base, s);
  // Paper eq. 37: gravity along the measured force, |g| = 9.80665 (the plan's).
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d f = s.wrench.row(i).head<3>();
    s.gravity.row(i) = kStandardGravity * f.normalized();
  }
  s.gravity_from_force = true;
  const IdentifySummary b = identify(model, base, s);
  EXPECT_LT((a.value - b.value).norm(), 1e-9 * a.value.norm());
  EXPECT_TRUE(b.gravity_from_force);
}

TEST(Estimation, OffsetsWithGravityFromForceAreRefused) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/ur_like/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  s.gravity_from_force = true;
  EXPECT_THROW(identify(model, base, s), IdentifiabilityError);
}

TEST(Estimation, UserSigmasScaleTheCovariance) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, so);
  IdentifyOptions o1, o2;
  o1.sigma_force = 0.05, o1.sigma_moment = 0.005;
  o2.sigma_force = 0.1, o2.sigma_moment = 0.01;
  const IdentifySummary a = identify(model, base, s, o1), b = identify(model, base, s, o2);
  EXPECT_FALSE(a.sigma_estimated);
  EXPECT_LT((b.stddev - 2 * a.stddev).norm(), 1e-12 * a.stddev.norm());
  EXPECT_LT((a.value - b.value).norm(), 1e-12 * a.value.norm());  // same weights ratio
  EXPECT_NEAR(a.chi2_per_dof, 1.0, 0.5);
}

TEST(Puma260, ConditionNumberIsThePapersEq36) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const IdentifySummary r = identify(model, base, s);
  const double paper = test::paper_condition_number(s);
  EXPECT_NEAR(r.condition_number, paper, 1e-9 * paper);
}

// The message of the IdentifiabilityError identify() must throw ("" if none).
std::string identifiability_message(const Model& model, const BaseParameters& base,
                                    const Samples& s) {
  try {
    identify(model, base, s);
  } catch (const IdentifiabilityError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected IdentifiabilityError";
  return "";
}

TEST(Puma260, OffsetsNeedMoreThanTwoGravityDirections) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("15 of the 16"), std::string::npos) << msg;
  EXPECT_NE(msg.find("offset_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

TEST(Estimation, AJointThatNeverMovesIsNamed) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.q.col(2).setConstant(0.3);  // joint3 held still
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("joint3"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("joint1"), std::string::npos) << msg;
}

TEST(Estimation, LevelOnlyDataNeedsATilt) {
  // With gravity always along z, the z first moments stay hidden (paper sec. III).
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  for (int i = 0; i < s.size(); ++i) s.gravity.row(i) << 0, 0, kStandardGravity;
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("p9"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

TEST(Estimation, UndeterminedParametersOfARobotWithoutJoints) {
  // The diagnosis of a robot without joints (N x 0 joint matrix; fuzz_csv
  // reached it first).
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/wrist_tool/wrist_tool.urdf");
  ASSERT_EQ(model.num_joints(), 0);
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/wrist_tool/plan.csv");
  for (int i = 0; i < s.size(); ++i) s.gravity.row(i) << 0, 0, kStandardGravity;
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

}  // namespace
}  // namespace massid

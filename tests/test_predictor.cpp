// The compiled predictor against the base regressor (w = Y_b pi_b + offset)
// for arbitrary parameter values, and against the URDF truth once identified.
#include <gtest/gtest.h>

#include <random>

#include "massid/base_parameters.hpp"
#include "massid/base_regressor.hpp"
#include "massid/estimation.hpp"
#include "massid/predictor.hpp"
#include "massid/simulate.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

class PredictorTest : public ::testing::TestWithParam<test::Example> {};

TEST_P(PredictorTest, EqualsTheBaseRegressorForAnyParameters) {
  const Model model = load_urdf(GetParam().urdf);
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  RegressorData reg(model, base);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd values(base.num_unknowns());
    for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
    const Predictor pred = compile_predictor(model, base, values);
    PredictorData data(pred);
    for (int k = 0; k < 20; ++k) {
      Eigen::VectorXd q(model.num_joints());
      for (int j = 0; j < model.num_joints(); ++j) q[j] = model.joints[j].generic_position(u(rng));
      const Eigen::Vector3d g(n(rng), n(rng), n(rng));
      base_regressor(model, base, reg, q, g);
      const Wrench expected = reg.base * values;
      EXPECT_LT((predict(pred, data, q, g) - expected).norm(), 1e-12 * (1 + expected.norm()));
    }
  }
}

TEST_P(PredictorTest, IdentifiedParametersPredictTheTruthAtNewPoses) {
  const Model model = load_urdf(GetParam().urdf);
  const BaseParameters base = find_base_parameters(model);
  Samples plan = test::load_plan(model, GetParam().plan);
  plan.wrench = simulate_wrenches(model, plan);
  const Predictor pred = compile_predictor(model, base, identify(model, base, plan).value);
  PredictorData data(pred);
  // New poses: the plan's gravity directions rotated, joints shifted.
  Samples fresh = plan;
  for (int i = 0; i < fresh.size(); ++i) {
    fresh.q.row(i).array() += 0.7;
    fresh.gravity.row(i) =
        Eigen::Vector3d(fresh.gravity(i, 1), fresh.gravity(i, 2), fresh.gravity(i, 0));
  }
  const Eigen::MatrixXd W = simulate_wrenches(model, fresh);
  for (int i = 0; i < fresh.size(); ++i) {
    const Wrench w =
        predict(pred, data, fresh.q.row(i).transpose(), fresh.gravity.row(i).transpose());
    EXPECT_LT((w - W.row(i).transpose()).norm(), 1e-9 * W.row(i).norm());
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, PredictorTest, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace massid

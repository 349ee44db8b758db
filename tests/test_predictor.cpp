// The compiled predictor against the base regressor (w + offset = Y_b pi_b +
// offset: predict() gives the mechanism's wrench, the offset kept beside it)
// for arbitrary parameter values, and against the URDF truth once identified.
#include <gtest/gtest.h>

#include <random>

#include "core/predictor_plan.hpp"
#include "core/vector_paths.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"
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
      EXPECT_LT((predict(pred, data, q, g) + pred.offset - expected).norm(),
                1e-12 * (1 + expected.norm()));
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

// The batch form computes row by row exactly what single calls compute.
TEST_P(PredictorTest, BatchEqualsSingleCalls) {
  const Model model = load_urdf(GetParam().urdf);
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n;
  Eigen::VectorXd values(base.num_unknowns());
  for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
  const Predictor pred = compile_predictor(model, base, values);
  PredictorData data(pred);
  const int N = 37;
  Eigen::MatrixXd Q(N, model.num_joints()), G(N, 3), W(N, 6);
  for (Eigen::Index i = 0; i < Q.size(); ++i) Q.data()[i] = 3 * n(rng);
  for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = 9.81 * n(rng);
  predict(pred, data, Q, G, W);
  for (int i = 0; i < N; ++i) {
    const Eigen::VectorXd q = Q.row(i).transpose();
    EXPECT_EQ(W.row(i).transpose(), predict(pred, data, q, G.row(i).transpose())) << "row " << i;
  }
}

// The four-lane (AVX2) path, chosen when the CPU has it, computes every lane
// as the two-lane (SSE2) path does: the same bits.
TEST_P(PredictorTest, FourLanesGiveTheSameBitsAsTwo) {
  if (!detail::cpu_has_avx2()) GTEST_SKIP() << "no AVX2 (an x86-64 without it, or another CPU)";
  const Model model = load_urdf(GetParam().urdf);
  const BaseParameters base = find_base_parameters(model);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n;
  Eigen::VectorXd values(base.num_unknowns());
  for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
  const Predictor four = detail::with_four_lanes(compile_predictor(model, base, values), true);
  const Predictor two = detail::with_four_lanes(four, false);
  PredictorData data4(four), data2(two);
  for (int i = 0; i < 200; ++i) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < q.size(); ++j) q[j] = 3 * n(rng);
    const Eigen::Vector3d g(n(rng), n(rng), -9.81);
    EXPECT_EQ(predict(four, data4, q, g), predict(two, data2, q, g)) << "sample " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, PredictorTest, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace massid

namespace massid {
namespace {

// The paper's claim (sec. V) in its own terms: identified from the 30-pose
// plan with sensor noise, the prediction at 200 held-out poses (tilts up to
// 25 deg in any direction) is within 1 % of each axis' range (Mz: 10 %). We
// require far better, and errors at the noise level against noisy data.
TEST(Puma260, HeldOutPredictionsAreFarInsideThePapersOnePercent) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples plan = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  SimulateOptions noise;
  noise.noise_force = 0.05;
  noise.noise_moment = 0.005;
  plan.wrench = simulate_wrenches(model, plan, noise);
  const Predictor pred = compile_predictor(model, base, identify(model, base, plan).value);
  PredictorData data(pred);

  Samples held = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/holdout.csv");
  const Eigen::MatrixXd truth = simulate_wrenches(model, held);
  noise.seed = 77;
  const Eigen::MatrixXd measured = simulate_wrenches(model, held, noise);
  Eigen::MatrixXd predicted(held.size(), 6);
  for (int i = 0; i < held.size(); ++i)
    predicted.row(i) =
        predict(pred, data, held.q.row(i).transpose(), held.gravity.row(i).transpose());
  const PredictionErrors model_error = prediction_errors(truth, predicted);
  const PredictionErrors vs_measured = prediction_errors(measured, predicted);
  for (int k = 0; k < 6; ++k) {
    EXPECT_LT(model_error.percent_of_range[k], 0.3) << kWrenchColumns[k];
    // Against noisy measurements the error is the noise itself.
    const double sigma = k < 3 ? noise.noise_force : noise.noise_moment;
    EXPECT_LT(vs_measured.rms[k], 1.25 * sigma) << kWrenchColumns[k];
    EXPECT_GT(vs_measured.rms[k], 0.8 * sigma) << kWrenchColumns[k];
  }
}

}  // namespace
}  // namespace massid

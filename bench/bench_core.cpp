// Timings of the core algorithms on the example robots: the real-time
// predictor, the regressors, identification and CSV reading.
#include <benchmark/benchmark.h>

#include <random>

#include "chain_robot.hpp"
#include "example_robots.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/design.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid;

using massid::bench::kRobotNames;
using massid::bench::kRobots;

// Random samples (joint positions and gravity) for a model.
Samples random_samples(const Model& model, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g;
  Samples s;
  s.source = "random";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j)
      s.q(i, j) = model.joints[j].generic_position(u(rng));
    s.gravity.row(i) = 9.81 * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  }
  return s;
}

// predict() on 1024 random samples of a model, in turn.
void time_predict(benchmark::State& state, const Model& model) {
  const BaseParameters base = find_base_parameters(model);
  const Predictor pred = compile_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  PredictorData data(pred);
  const Samples s = random_samples(model, 1024, 1);
  // One contiguous column per sample (a row of s.q would be copied into the
  // Ref<const VectorXd>, an allocation per call).
  const Eigen::MatrixXd q = s.q.transpose(), g = s.gravity.transpose();
  int i = 0;
  for (auto _ : state) {
    const Wrench w = predict(pred, data, q.col(i), Eigen::Vector3d(g.col(i)));
    benchmark::DoNotOptimize(w);
    i = (i + 1) & 1023;
  }
}

void BM_Predict(benchmark::State& state) {
  time_predict(state, load_urdf(kRobots[state.range(0)]));
  state.SetLabel(kRobotNames[state.range(0)]);
}
BENCHMARK(BM_Predict)->DenseRange(0, 2);

// How the predictor's cost grows with the number of joints (serial chains).
void BM_PredictChain(benchmark::State& state) {
  const Model model = bench::chain_robot(static_cast<int>(state.range(0)));
  time_predict(state, model);
  state.counters["joints"] = static_cast<double>(model.num_joints());
  state.counters["ns_per_joint"] = benchmark::Counter(
      static_cast<double>(model.num_joints()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_PredictChain)->Arg(3)->Arg(6)->Arg(12)->Arg(24);

// predict_motion() on 1024 random samples (positions, velocities,
// accelerations, gravity) of a model, in turn: the wrench in motion.
void time_predict_motion(benchmark::State& state, const Model& model) {
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  const BaseParameters base = find_base_parameters(model, o);
  const MotionPredictor pred =
      compile_motion_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  MotionPredictorData data(pred);
  const Samples s = random_samples(model, 1024, 1);
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n;
  const Eigen::MatrixXd q = s.q.transpose(), g = s.gravity.transpose();  // a column per sample
  Eigen::MatrixXd qd(q.rows(), q.cols()), qdd(q.rows(), q.cols());
  for (Eigen::Index i = 0; i < qd.size(); ++i)
    qd.data()[i] = 2 * n(rng), qdd.data()[i] = 5 * n(rng);
  int i = 0;
  for (auto _ : state) {
    const Wrench w = predict_motion(pred, data, q.col(i).data(), qd.col(i).data(),
                                    qdd.col(i).data(), Eigen::Vector3d(g.col(i)));
    benchmark::DoNotOptimize(w);
    i = (i + 1) & 1023;
  }
}

void BM_PredictMotion(benchmark::State& state) {
  time_predict_motion(state, load_urdf(kRobots[state.range(0)]));
  state.SetLabel(kRobotNames[state.range(0)]);
}
BENCHMARK(BM_PredictMotion)->DenseRange(0, 2);

void BM_PredictMotionChain(benchmark::State& state) {
  const Model model = bench::chain_robot(static_cast<int>(state.range(0)));
  time_predict_motion(state, model);
  state.counters["joints"] = static_cast<double>(model.num_joints());
  state.counters["ns_per_joint"] = benchmark::Counter(
      static_cast<double>(model.num_joints()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_PredictMotionChain)->Arg(3)->Arg(6)->Arg(12)->Arg(24);

void BM_StandardRegressor(benchmark::State& state) {
  const Model model = load_urdf(kRobots[state.range(0)]);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, num_standard_parameters(model));
  const Samples s = random_samples(model, 1024, 2);
  int i = 0;
  for (auto _ : state) {
    forward_kinematics(model, kin, s.q.row(i).transpose());
    standard_regressor(model, kin, s.gravity.row(i).transpose(), Y);
    benchmark::DoNotOptimize(Y.data());
    i = (i + 1) & 1023;
  }
  state.SetLabel(kRobotNames[state.range(0)]);
}
BENCHMARK(BM_StandardRegressor)->DenseRange(0, 2);

// forward_kinematics with velocities and accelerations (the one recursion
// behind the motion regressor and the streamed motion rows).
void BM_ForwardKinematicsMotion(benchmark::State& state) {
  const Model model = load_urdf(kRobots[state.range(0)]);
  KinematicsData kin(model);
  const Samples s = random_samples(model, 1024, 2);
  const Eigen::VectorXd qd = Eigen::VectorXd::Constant(model.num_joints(), 0.7);
  const Eigen::VectorXd qdd = Eigen::VectorXd::Constant(model.num_joints(), -1.3);
  int i = 0;
  for (auto _ : state) {
    forward_kinematics(model, kin, s.q.row(i).transpose(), qd, qdd, s.gravity.row(i).transpose());
    benchmark::DoNotOptimize(kin.accel.data());
    i = (i + 1) & 1023;
  }
  state.SetLabel(kRobotNames[state.range(0)]);
}
BENCHMARK(BM_ForwardKinematicsMotion)->DenseRange(0, 2);

void BM_FindBaseParameters(benchmark::State& state) {
  const Model model = load_urdf(kRobots[state.range(0)]);
  for (auto _ : state) benchmark::DoNotOptimize(find_base_parameters(model));
  state.SetLabel(kRobotNames[state.range(0)]);
}
BENCHMARK(BM_FindBaseParameters)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void BM_Identify(benchmark::State& state) {
  const Model model = load_urdf(kRobots[1]);
  const BaseParameters base = find_base_parameters(model);
  Samples s = random_samples(model, static_cast<int>(state.range(0)), 3);
  SimulateOptions noise;
  noise.noise_force = 0.05;
  noise.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, noise);
  for (auto _ : state) benchmark::DoNotOptimize(identify(model, base, s));
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetLabel("ur_like, rows/s");
}
BENCHMARK(BM_Identify)->Arg(30)->Arg(1000)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_ParseCsv(benchmark::State& state) {
  const Model model = load_urdf(kRobots[1]);
  Samples s = random_samples(model, static_cast<int>(state.range(0)), 4);
  s.wrench = simulate_wrenches(model, s);
  std::string text = "j1,j2,j3,j4,j5,j6,gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < s.size(); ++i) {
    for (int j = 0; j < 6; ++j) text += format_number(s.q(i, j)) + ",";
    for (int j = 0; j < 3; ++j) text += format_number(s.gravity(i, j)) + ",";
    for (int j = 0; j < 6; ++j) text += format_number(s.wrench(i, j)) + (j < 5 ? "," : "\n");
  }
  for (auto _ : state) benchmark::DoNotOptimize(parse_csv(text, "bench.csv"));
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(text.size()));
}
BENCHMARK(BM_ParseCsv)->Arg(10000)->Unit(benchmark::kMillisecond);

// The speed targets: a 30-pose PUMA 260 plan (paper's tilts, and any
// tilt up to 25 deg in 4 groups) under 2 s, a 60-pose ur_like plan under 10 s.
void BM_Design(benchmark::State& state) {
  const bool puma = state.range(0) < 2;
  const Model model = load_urdf(kRobots[puma ? 0 : 1]);
  const BaseParameters base = find_base_parameters(model);
  DesignOptions o;
  o.poses = puma ? 30 : 60;
  if (puma) o.level_gravity = Eigen::Vector3d(0, 0, kStandardGravity);
  if (state.range(0) == 0) {
    o.tilts = {{0, 0}, {0, 25 * 3.141592653589793 / 180}};
  } else {
    o.tilt_max = (puma ? 25 : 30) * 3.141592653589793 / 180;
    o.tilt_groups = 4;
  }
  double cond = 0;
  for (auto _ : state) cond = design(model, base, o).condition_number;
  state.counters["cond"] = cond;
  state.SetLabel(state.range(0) == 0   ? "puma260 30 poses, tilts 0:0,0:25"
                 : state.range(0) == 1 ? "puma260 30 poses, tilt-max 25"
                                       : "ur_like 60 poses, tilt-max 30");
}
BENCHMARK(BM_Design)->DenseRange(0, 2)->Unit(benchmark::kSecond)->Iterations(1);

// Issue 15's target for design --dynamic: a 30 s ur_like trajectory at
// 1000 Hz (the CLI's defaults: 5 harmonics, period 10 s, 6000 evaluations,
// min-height 5 cm) under 60 s, its condition number at least 3x better than
// the median of 20 random trajectories within the same limits (counters
// cond, random_median, ratio).
void BM_DesignDynamic(benchmark::State& state) {
  const Model model = load_urdf(kRobots[1]);
  ExcitationOptions o;
  o.min_height = kDefaultMinHeight;
  o.noise_force = 0.05;  // the CLI's defaults
  o.noise_moment = 0.005;
  BaseParameterOptions bo;
  bo.layout = ParameterLayout::full();
  bo.fixed_gravity = true;
  bo.sensor_gravity = o.level_gravity;
  const BaseParameters base = find_base_parameters(model, bo);
  ExcitationSummary s;
  for (auto _ : state) s = design_excitation(model, base, o);
  state.counters["cond"] = s.condition_number;
  state.counters["random_median"] = s.random_median;
  state.counters["ratio"] = s.random_median / s.grid_figure;
  state.counters["evaluations"] = s.evaluations;
  state.SetLabel("ur_like 30 s at 1000 Hz, 5 harmonics");
}
BENCHMARK(BM_DesignDynamic)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();

#include "bench_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "options.hpp"

namespace massid::cli {

void add_bench_command(CLI::App& app, BenchCommand& c) {
  c.app = app.add_subcommand(
      "bench", "Time the predictor, the regressor and identification on this machine and robot");
  c.app->add_option("robot", c.urdf, "Robot URDF")->required();
  c.app->add_option("--sensor", c.sensor, "Sensor link (default: the URDF root link)");
  c.app->add_option("--rows", c.rows, "Samples for the identification timings (default 100000)")
      ->check(CLI::Range(1000, 100000000));
  c.app->add_flag("--json", c.json,
                  "Print JSON (predict_ns, predict_dynamic_ns, regressor_ns, identify_rows_per_s, "
                  "identify_csv_rows_per_s)");
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Calls f(i) for i = 0, 1, ... until at least 0.3 s have passed; seconds per call.
template <typename F>
double time_per_call(F&& f) {
  long calls = 0;
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  do {
    for (int k = 0; k < 1024; ++k) f(static_cast<int>(calls++ & 1023));
    elapsed = seconds_since(t0);
  } while (elapsed < 0.3);
  return elapsed / static_cast<double>(calls);
}

// Random poses within the joint limits and gravity directions, with the
// URDF's wrench plus sensor-like noise.
Samples random_samples(const Model& model, int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g;
  Samples s;
  s.source = "bench";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  s.line.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j)
      s.q(i, j) = model.joints[j].generic_position(u(rng));
    s.gravity.row(i) = kStandardGravity * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  }
  SimulateOptions noise;
  noise.noise_force = 0.05;
  noise.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, noise);
  return s;
}

}  // namespace

int run_bench(const BenchCommand& c) {
  const Model model = load_urdf(c.urdf, c.sensor);
  const BaseParameters base = find_base_parameters(model);
  const Samples s = random_samples(model, c.rows);
  const Eigen::MatrixXd q = s.q.transpose(), g = s.gravity.transpose();  // a column per sample

  const Predictor pred = compile_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  PredictorData pdata(pred);
  double sink = 0.0;
  const double predict_s = time_per_call(
      [&](int i) { sink += predict(pred, pdata, q.col(i), Eigen::Vector3d(g.col(i)))[4]; });
  // The wrench in motion (motion_predictor.hpp) from dynamic base parameters,
  // at random joint rates and accelerations.
  BaseParameterOptions dynamic_options;
  dynamic_options.layout = ParameterLayout::full();
  const BaseParameters dynamic_base = find_base_parameters(model, dynamic_options);
  const MotionPredictor mpred = compile_motion_predictor(
      model, dynamic_base, Eigen::VectorXd::Ones(dynamic_base.num_unknowns()));
  MotionPredictorData mdata(mpred);
  Eigen::MatrixXd qd(q.rows(), 1024), qdd(q.rows(), 1024);  // time_per_call: i < 1024
  {
    std::mt19937_64 rng(2);
    std::normal_distribution<double> n;
    for (Eigen::Index i = 0; i < qd.size(); ++i)
      qd.data()[i] = 2 * n(rng), qdd.data()[i] = 5 * n(rng);
  }
  const double predict_dynamic_s = time_per_call([&](int i) {
    const Eigen::Index k = i % q.cols();
    sink += predict_motion(mpred, mdata, q.col(k).data(), qd.col(i).data(), qdd.col(i).data(),
                           Eigen::Vector3d(g.col(k)))[4];
  });
  RegressorData rdata(model, base);
  const double regressor_s = time_per_call([&](int i) {
    base_regressor(model, base, rdata, q.col(i), Eigen::Vector3d(g.col(i)));
    sink += rdata.base(4, 0);
  });

  auto t0 = Clock::now();
  const IdentifySummary memory = identify_streaming(model, base, s);
  const double identify_s = seconds_since(t0);

  // The same samples as a CSV file in the temporary directory, then identified from it.
  const std::filesystem::path csv =
      std::filesystem::temp_directory_path() / fmt::format("massid_bench_{}.csv", ::getpid());
  {
    std::vector<std::string> header;
    for (const Joint& j : model.joints) header.push_back(j.name);
    for (const char* k : {"gx", "gy", "gz"}) header.push_back(k);
    for (const char* k : kWrenchColumns) header.push_back(k);
    std::vector<std::vector<std::string>> rows(static_cast<std::size_t>(s.size()));
    for (int i = 0; i < s.size(); ++i) {
      auto& r = rows[static_cast<std::size_t>(i)];
      for (int j = 0; j < model.num_joints(); ++j) r.push_back(format_number(s.q(i, j)));
      for (int k = 0; k < 3; ++k) r.push_back(format_number(s.gravity(i, k)));
      for (int k = 0; k < 6; ++k) r.push_back(format_number(s.wrench(i, k)));
    }
    write_csv(csv.string(), header, rows);
  }
  t0 = Clock::now();
  IdentifySummary from_csv;
  try {
    from_csv = identify_csv(model, base, csv.string());
  } catch (...) {
    std::filesystem::remove(csv);
    throw;
  }
  const double csv_s = seconds_since(t0);
  const auto csv_bytes = std::filesystem::file_size(csv);
  std::filesystem::remove(csv);
  if (!(sink == sink) || (memory.value - from_csv.value).norm() > 1e-6 * memory.value.norm())
    throw std::runtime_error("bench: identification from memory and from CSV disagree");

  const double rows = c.rows;
  if (c.json) {
    nlohmann::ordered_json j;
    j["robot"] = model.name;
    j["joints"] = model.num_joints();
    j["base_parameters"] = base.num_unknowns();
    j["predict_ns"] = 1e9 * predict_s;
    j["predict_dynamic_ns"] = 1e9 * predict_dynamic_s;
    j["regressor_ns"] = 1e9 * regressor_s;
    j["rows"] = c.rows;
    j["identify_rows_per_s"] = rows / identify_s;
    j["identify_csv_rows_per_s"] = rows / csv_s;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{} ({} joints, {} base parameters) on this machine:\n", model.name,
                           model.num_joints(), base.num_unknowns());
  std::cout << fmt::format("  predict (gravity wrench, identified parameters)  {:10.1f} ns/call\n",
                           1e9 * predict_s);
  std::cout << fmt::format("  predict in motion (weight and inertial forces)   {:10.1f} ns/call\n",
                           1e9 * predict_dynamic_s);
  std::cout << fmt::format(
      "  base regressor                                   {:10.1f} ns/sample\n", 1e9 * regressor_s);
  std::cout << fmt::format("  identify, {} samples in memory              {:10.3g} rows/s\n",
                           c.rows, rows / identify_s);
  std::cout << fmt::format("  identify from CSV ({:.3g} MB)                    {:10.3g} rows/s\n",
                           csv_bytes / 1e6, rows / csv_s);
  std::cout << fmt::format("a 1 kHz loop has 1e6 ns per tick: the predictor takes {:.2g} % of it\n",
                           1e-4 * 1e9 * predict_s);
  return 0;
}

}  // namespace massid::cli

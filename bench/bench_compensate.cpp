// `massid compensate`'s per-line path (compensator.hpp), as the command times
// it for --stats: parse one CSV line, predict, format the output line (the
// pipe or socket I/O excluded). Lines as `simulate` writes them: shortest
// round-trip numbers (about 17 significant digits), 1024 lines in turn.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "example_robots.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/parameters.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"

namespace {

using namespace massid;

using massid::bench::kRobots;

// Header and 1024 lines of random samples: joints, (with motion) their _vel
// and _acc, gx,gy,gz, fx..mz.
std::vector<std::string> stream_lines(const Model& model, bool motion) {
  std::string header;
  for (const Joint& j : model.joints) header += j.name + ",";
  if (motion) {
    for (const Joint& j : model.joints) header += j.name + "_vel,";
    for (const Joint& j : model.joints) header += j.name + "_acc,";
  }
  header += "gx,gy,gz,fx,fy,fz,mx,my,mz";
  std::vector<std::string> lines{header};
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  for (int i = 0; i < 1024; ++i) {
    std::string line;
    for (const Joint& j : model.joints) line += format_number(j.generic_position(u(rng))) + ",";
    if (motion)
      for (int k = 0; k < 2 * model.num_joints(); ++k) line += format_number(3 * n(rng)) + ",";
    const Eigen::Vector3d g =
        kStandardGravity * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    for (int k = 0; k < 3; ++k) line += format_number(g[k]) + ",";
    for (int k = 0; k < 6; ++k) line += format_number(10 * n(rng)) + (k < 5 ? "," : "");
    lines.push_back(line);
  }
  return lines;
}

void time_compensate(benchmark::State& state, bool motion) {
  const Model model = load_urdf(kRobots[state.range(0)]);
  BaseParameterOptions options;
  options.offset = true;
  if (motion) options.layout = ParameterLayout::full();
  const BaseParameters base = find_base_parameters(model, options);
  const std::vector<std::string> lines = stream_lines(model, motion);
  Compensator comp(IdentifiedModel::from_values(
                       model, base, Eigen::VectorXd::Constant(base.num_unknowns(), 0.1)),
                   lines[0], "bench");
  std::size_t i = 0, bytes = 0;
  for (auto _ : state) {
    const std::string_view out = comp.compensate(lines[1 + i], static_cast<int>(i + 2));
    benchmark::DoNotOptimize(out.data());
    bytes += out.size();
    i = (i + 1) & 1023;
  }
  state.counters["out_bytes_per_line"] =
      static_cast<double>(bytes) / static_cast<double>(state.iterations());
}

// Static params file: the gravity wrench.
void BM_Compensate(benchmark::State& state) { time_compensate(state, false); }
BENCHMARK(BM_Compensate)->DenseRange(0, 2);

// Dynamic params file with JOINT_vel, JOINT_acc: the full wrench.
void BM_CompensateMotion(benchmark::State& state) { time_compensate(state, true); }
BENCHMARK(BM_CompensateMotion)->DenseRange(0, 2);

}  // namespace

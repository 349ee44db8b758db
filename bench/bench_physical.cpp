// fit_physical (physical.hpp) after a dynamic identification: a 7-joint
// chain (chain_robot.hpp) and the Panda, on a level platform with offsets,
// from a well-exciting log and from a short, noisy one. Only the solve is
// timed; the identification is made once.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "chain_robot.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/physical.hpp"
#include "massid/io/urdf.hpp"

namespace massid::bench {
namespace {

struct Fit {
  Model model;
  BaseParameters base;
  IdentifySummary summary;
};

// `noise` N (a tenth of it in N m) on a log of `duration` s at 200 Hz.
Fit fit_of(Model model, double duration, double noise) {
  Fit f{std::move(model), {}, {}};
  Samples s = sample_trajectory(random_fourier_trajectory(f.model, 5, 10.0, 1), duration, 200.0,
                                Eigen::Vector3d(0, 0, -9.80665));
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = noise;
  so.noise_moment = noise / 10;
  so.offset << 1, 2, 3, 0.1, 0.2, 0.3;
  s.wrench = simulate_wrenches(f.model, s, so);
  f.base = find_base_parameters(f.model, motion_base_options(s, true));
  f.summary = identify(f.model, f.base, s);
  return f;
}

Model panda() {
  const std::string path = "/work/shared/robots/panda.urdf";
  return std::filesystem::exists(path) ? load_urdf(path) : chain_robot(7);
}

void time_fit(benchmark::State& state, const Fit& f) {
  PhysicalSummary p;
  for (auto _ : state) {
    p = fit_physical(f.model, f.base, f.summary);
    benchmark::DoNotOptimize(p.standard.data());
  }
  state.counters["iterations"] = p.iterations;
  state.counters["worst_mismatch_std"] = std::abs(p.worst_mismatch);
  state.counters["base_parameters"] = f.base.num_mass();
  state.counters["consistent"] = p.consistent();
}

// 0: well excited (20 s, 0.1 N); 1: short and noisy (3 s, 20 N).
void BM_FitPhysicalChain7(benchmark::State& state) {
  static const Fit fits[2] = {fit_of(chain_robot(7), 20.0, 0.1), fit_of(chain_robot(7), 3.0, 20.0)};
  time_fit(state, fits[state.range(0)]);
}
BENCHMARK(BM_FitPhysicalChain7)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_FitPhysicalPanda(benchmark::State& state) {
  static const Fit fits[2] = {fit_of(panda(), 20.0, 0.1), fit_of(panda(), 3.0, 20.0)};
  time_fit(state, fits[state.range(0)]);
}
BENCHMARK(BM_FitPhysicalPanda)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace massid::bench

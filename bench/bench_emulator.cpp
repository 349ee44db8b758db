// The space emulator's control step (target: under 5 us at 1 kHz).
#include <benchmark/benchmark.h>

#include "massid/base_parameters.hpp"
#include "massid/emulator/controller.hpp"
#include "massid/regressor.hpp"

namespace {

using namespace massid;
using namespace massid::emulator;

void BM_ControlStep(benchmark::State& state) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  EmulatorModel em;
  em.predictor = compile_predictor(model, base, base.K * nominal_standard_parameters(model));
  em.spacecraft.mass = 50.0;
  em.spacecraft.inertia = Eigen::Vector3d(6.0, 7.0, 5.0).asDiagonal();
  em.geometry = default_geometry();
  EmulatorData data(em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.1, -1.2, 0.9);
  Wrench measured = Wrench::Zero();
  measured << 0.01, 0.02, -103.9, 0.3, -0.2, 0.0;
  int k = 0;
  for (auto _ : state) {
    control_step(em, data, measured, q, data.command);
    benchmark::DoNotOptimize(data.legs);
    if (++k == 1000) reset(em, data), k = 0;  // stay inside the workspace
  }
}
BENCHMARK(BM_ControlStep);

}  // namespace

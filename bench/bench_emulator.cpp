// The space emulator: the control step alone (target: under 5 us at 1 kHz) and
// the whole simulation, plant, controller and free-floating reference (target:
// at least 20x faster than real time at 1 kHz).
#include <benchmark/benchmark.h>

#include "massid/core/base_parameters.hpp"
#include "massid/core/regressor.hpp"
#include "massid/emulator/controller.hpp"
#include "massid/emulator/emulation.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid;
using namespace massid::emulator;

void BM_ControlStep(benchmark::State& state) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  EmulatorModel em;
  em.identified =
      IdentifiedModel::from_values(model, base, base.K * nominal_standard_parameters(model));
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

// One iteration: 2 s of the README's maneuver (PUMA 260, 50 kg spacecraft, 1 kHz).
void BM_EmulationTwoSeconds(benchmark::State& state) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  const IdentifiedModel truth =
      IdentifiedModel::from_values(model, base, base.K * nominal_standard_parameters(model));
  EmulationOptions o;
  o.duration = 2.0;
  o.spacecraft.mass = 50.0;
  o.spacecraft.inertia = Eigen::Vector3d(5.0, 5.0, 5.0).asDiagonal();
  o.platform_T_sensor.linear() =
      Eigen::AngleAxisd(3.141592653589793, Eigen::Vector3d::UnitX()).toRotationMatrix();
  o.trajectory = smooth_maneuver(model, 10.0);  // the first 2 s of the 10 s maneuver
  double seconds = 0.0;
  for (auto _ : state) {
    const EmulationSummary s = run_emulation(model, truth, o, true);
    benchmark::DoNotOptimize(s.position_error_max_m);
    seconds += s.seconds;
  }
  state.counters["realtime_factor"] =
      o.duration * static_cast<double>(state.iterations()) / seconds;
}
BENCHMARK(BM_EmulationTwoSeconds)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

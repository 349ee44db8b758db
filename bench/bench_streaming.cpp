// Streaming identification (streaming.hpp) of the six-joint ur_like robot from
// memory and from CSV at 10^3 ... 10^6 rows, rows/s as a counter, with the
// dense Eigen QR identification (identify()) on the same data as the anchor.
// The CSV files are generated into a temporary directory, once per size.
// In motion (the full layout, 50 unknowns with offsets): the accumulator fed
// from memory, and motion logs streamed from CSV with the velocities given or
// derived by the filter in the stream.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid;
namespace fs = std::filesystem;

const char* const kUrLike = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";

struct StreamFixture {
  Model model = load_urdf(kUrLike);
  BaseParameters base = find_base_parameters(model);
};
const StreamFixture& fixture() {
  static const StreamFixture f;
  return f;
}

// Random poses, tilts up to ~30 degrees, noisy simulated wrenches.
Samples make_samples(const Model& model, int n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Samples s;
  s.source = "bench";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j)
      s.q(i, j) = model.joints[j].generic_position(u(rng));
    const double tilt = 0.5 * u(rng), az = 6.283 * u(rng);
    s.gravity.row(i) =
        -kStandardGravity * Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                            std::sin(tilt) * std::sin(az), std::cos(tilt));
  }
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, so);
  return s;
}

const Samples& samples(int n) {
  static std::map<int, Samples> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, make_samples(fixture().model, n)).first;
  return it->second;
}

// A data CSV of n rows (shortest round-trip numbers) in a temporary directory,
// removed at exit.
struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("massid_bench_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(dir); }
  ~TempDir() { fs::remove_all(dir); }
};
std::string csv_file(int n) {
  static TempDir tmp;
  const std::string path = (tmp.dir / ("ur_like_" + std::to_string(n) + ".csv")).string();
  if (fs::exists(path)) return path;
  const Model& model = fixture().model;
  const Samples& s = samples(n);
  std::ofstream out(path);
  for (const auto& j : model.joints) out << j.name << ",";
  out << "gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  std::string line;
  for (int i = 0; i < n; ++i) {
    line.clear();
    for (int j = 0; j < s.q.cols(); ++j) line += format_number(s.q(i, j)) + ",";
    for (int k = 0; k < 3; ++k) line += format_number(s.gravity(i, k)) + ",";
    for (int k = 0; k < 6; ++k) line += format_number(s.wrench(i, k)) + (k < 5 ? "," : "\n");
    out << line;
  }
  return path;
}

void set_rate(benchmark::State& state, int n) {
  state.counters["rows/s"] =
      benchmark::Counter(static_cast<double>(n) * state.iterations(), benchmark::Counter::kIsRate);
}

// Dense anchor: identify() builds the 6N x p stacked regressor and QRs it.
void BM_IdentifyDense(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Samples& s = samples(n);
  for (auto _ : state) benchmark::DoNotOptimize(identify(fixture().model, fixture().base, s));
  set_rate(state, n);
}
BENCHMARK(BM_IdentifyDense)
    ->RangeMultiplier(10)
    ->Range(1000, 100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Streaming from memory; range(1): threads.
void BM_IdentifyStreaming(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Samples& s = samples(n);
  StreamOptions so;
  so.threads = static_cast<int>(state.range(1));
  for (auto _ : state)
    benchmark::DoNotOptimize(identify_streaming(fixture().model, fixture().base, s, {}, so));
  set_rate(state, n);
}
BENCHMARK(BM_IdentifyStreaming)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Streaming from a CSV file (page cache warm): range(1) threads, range(2) 1
// with the residual_max pass, 0 without.
void BM_IdentifyCsv(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::string path = csv_file(n);
  StreamOptions so;
  so.threads = static_cast<int>(state.range(1));
  so.residual_max = state.range(2) != 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(identify_csv(fixture().model, fixture().base, path, {}, so));
  set_rate(state, n);
  state.counters["MB/s"] =
      benchmark::Counter(static_cast<double>(fs::file_size(path)) * state.iterations() / 1e6,
                         benchmark::Counter::kIsRate);
}
BENCHMARK(BM_IdentifyCsv)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {1, 2}, {1}})
    ->Args({1000000, 2, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---------------------------------------------------------------- motion

// A 1 kHz motion log of ur_like along a random exciting trajectory (level
// gravity), noisy wrenches with an offset: the samples, with velocities.
const Samples& motion_samples(int n) {
  static std::map<int, Samples> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const Model& model = fixture().model;
  const FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 3);
  Samples s =
      sample_trajectory(tr, (n - 1) / 1000.0, 1000.0, Eigen::Vector3d(0.0, 0.0, -kStandardGravity));
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  so.offset << 2.0, -1.0, 3.0, 0.2, -0.1, 0.05;
  s.wrench = simulate_wrenches(model, s, so);
  return cache.emplace(n, std::move(s)).first->second;
}

const BaseParameters& motion_base() {
  static const BaseParameters base = find_base_parameters(
      fixture().model, motion_base_options(motion_samples(1000), /*offset=*/true));
  return base;
}

// The motion accumulator alone (one thread): regressor rows in the sensor
// frame, six per-axis Householder folds over ~47 columns, then finish().
void BM_MotionAccumulator(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Samples& s = motion_samples(n);
  for (auto _ : state) {
    IdentifyAccumulator acc(fixture().model, motion_base());
    acc.add(s);
    benchmark::DoNotOptimize(acc.finish());
  }
  set_rate(state, n);
  state.counters["unknowns"] = motion_base().num_unknowns();
}
BENCHMARK(BM_MotionAccumulator)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// Dense anchor in motion: identify() on the stacked 6N x 50 regressor.
void BM_MotionIdentifyDense(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Samples& s = motion_samples(n);
  for (auto _ : state) benchmark::DoNotOptimize(identify(fixture().model, motion_base(), s));
  set_rate(state, n);
}
BENCHMARK(BM_MotionIdentifyDense)->Arg(10000)->Unit(benchmark::kMillisecond);

// A motion CSV of n rows: t, joints, (JOINT_vel, JOINT_acc,) gx..gz, fx..mz.
std::string motion_csv(int n, bool velocities) {
  static TempDir tmp;
  const std::string path =
      (tmp.dir / ("motion_" + std::to_string(n) + (velocities ? "_vel" : "_pos") + ".csv"))
          .string();
  if (fs::exists(path)) return path;
  const Model& model = fixture().model;
  const Samples& s = motion_samples(n);
  std::ofstream out(path);
  out << "t";
  for (const auto& j : model.joints) out << "," << j.name;
  if (velocities) {
    for (const auto& j : model.joints) out << "," << j.name << "_vel";
    for (const auto& j : model.joints) out << "," << j.name << "_acc";
  }
  out << ",gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  std::string line;
  const auto cell = [&](double v) {
    line += ',';
    line += format_number(v);
  };
  for (int i = 0; i < n; ++i) {
    line = format_number(s.time[i]);
    for (int j = 0; j < s.q.cols(); ++j) cell(s.q(i, j));
    if (velocities) {
      for (int j = 0; j < s.qd.cols(); ++j) cell(s.qd(i, j));
      for (int j = 0; j < s.qdd.cols(); ++j) cell(s.qdd(i, j));
    }
    for (int k = 0; k < 3; ++k) cell(s.gravity(i, k));
    for (int k = 0; k < 6; ++k) cell(s.wrench(i, k));
    line += '\n';
    out << line;
  }
  return path;
}

// identify_motion_csv (what `massid identify --dynamic` streams): range(1)
// threads, range(2) 1 with the velocities in the file, 0 derived by the filter.
void BM_IdentifyMotionCsv(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool velocities = state.range(2) != 0;
  const std::string path = motion_csv(n, velocities);
  StreamOptions so;
  so.threads = static_cast<int>(state.range(1));
  for (auto _ : state)
    benchmark::DoNotOptimize(identify_motion_csv(fixture().model, path, true, {}, {}, so));
  set_rate(state, n);
  state.counters["MB/s"] =
      benchmark::Counter(static_cast<double>(fs::file_size(path)) * state.iterations() / 1e6,
                         benchmark::Counter::kIsRate);
}
BENCHMARK(BM_IdentifyMotionCsv)
    ->ArgsProduct({{100000, 1000000}, {1, 2}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

// The static and the motion predictor against wrenches computed on x86-64
// (tests/data/predictor_reference.txt): every vector path, two lanes or four,
// x86-64 or aarch64 (scripts/arm.sh runs this test under qemu), gives them to
// within 1 ulp per component.
//
// The inputs come from a generator specified here to the bit: the raw output
// of std::mt19937_64 (fixed by the standard, unlike its distributions), scaled
// by hand. Only the wrenches are stored, as hex floats. To rewrite the
// reference after a deliberate change of the predictors' arithmetic, on x86-64:
//
//   export MASSID_WRITE_REFERENCE=$PWD/tests/data/predictor_reference.txt
//   build/dev/tests/massid_tests --gtest_filter='PredictorReference.*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/motion_predictor_plan.hpp"
#include "core/predictor_plan.hpp"
#include "core/vector_paths.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/io/urdf.hpp"
#include "ulps.hpp"

namespace massid {
namespace {

const char* const kReference = MASSID_SOURCE_DIR "/tests/data/predictor_reference.txt";
constexpr int kSamples = 20;  // per robot and predictor

// Serial, tree with general axes and a prismatic joint, mimic joints.
struct Robot {
  const char* name;
  const char* urdf;
};
const Robot kRobots[] = {
    {"puma260", MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf"},
    {"ur_like", MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf"},
    {"branching", MASSID_SOURCE_DIR "/examples/branching/branching.urdf"},
    {"panda", MASSID_SOURCE_DIR "/tests/data/robots/panda.urdf"},
};

// Uniform in [lo, hi) from the top 53 bits of one raw draw (u exact; then a
// multiply and an add, rounded the same everywhere).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1p-53);
}

// n of them, drawn in order.
Eigen::VectorXd uniform(std::mt19937_64& rng, int n, double lo, double hi) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = uniform(rng, lo, hi);
  return v;
}

// One predicted wrench: which robot and predictor, which sample.
struct Row {
  std::string robot, kind;
  int sample = 0;
  Wrench w = Wrench::Zero();
};

// Every row, in file order, from the path the predictors take when four_lanes
// is as given (true: AVX2, x86-64 CPUs that have it only).
std::vector<Row> predict_all(bool four_lanes) {
  std::vector<Row> rows;
  for (const Robot& robot : kRobots) {
    const Model model = load_urdf(robot.urdf);
    const int nj = model.num_joints();
    std::mt19937_64 rng(2026);
    {  // static: the base parameters with offsets, q, g
      BaseParameterOptions o;
      o.offset = true;
      const BaseParameters base = find_base_parameters(model, o);
      const Eigen::VectorXd values = uniform(rng, base.num_unknowns(), -1.0, 1.0);
      const Predictor pred =
          detail::with_four_lanes(compile_predictor(model, base, values), four_lanes);
      PredictorData data(pred);
      for (int k = 0; k < kSamples; ++k) {
        const Eigen::VectorXd q = uniform(rng, nj, -3.0, 3.0);
        const Eigen::Vector3d g = uniform(rng, 3, -9.81, 9.81);
        // The reference holds what the sensor reads (offsets added): predict()
        // gives the mechanism's wrench, the offset added here as the reference
        // was computed (one addition per component, the same bits).
        rows.push_back({robot.name, "static", k, predict(pred, data, q, g) + pred.offset});
      }
    }
    {  // motion: the dynamic base parameters of a moving sensor, q, qd, qdd, g, the sensor's motion
      BaseParameterOptions o;
      o.layout = ParameterLayout::full();
      o.offset = true;
      o.sensor_moving = true;
      const BaseParameters base = find_base_parameters(model, o);
      const Eigen::VectorXd values = uniform(rng, base.num_unknowns(), -1.0, 1.0);
      const MotionPredictor pred =
          detail::with_four_lanes(compile_motion_predictor(model, base, values), four_lanes);
      MotionPredictorData data(pred);
      for (int k = 0; k < kSamples; ++k) {
        Eigen::VectorXd q(nj), qd(nj), qdd(nj);
        for (int j = 0; j < nj; ++j) {
          q[j] = uniform(rng, -3.0, 3.0);
          qd[j] = uniform(rng, -2.0, 2.0);
          qdd[j] = uniform(rng, -5.0, 5.0);
        }
        const Eigen::Vector3d g = uniform(rng, 3, -9.81, 9.81);
        FrameMotion sensor;
        for (int i = 0; i < 3; ++i) {
          sensor.omega[i] = uniform(rng, -1.0, 1.0);
          sensor.omega_dot[i] = uniform(rng, -3.0, 3.0);
          sensor.accel[i] = uniform(rng, -3.0, 3.0);
        }
        rows.push_back({robot.name, "motion", k,
                        predict_motion(pred, data, q.data(), qd.data(), qdd.data(), g, sensor)});
      }
    }
  }
  return rows;
}

std::string format(const std::vector<Row>& rows) {
  std::string out =
      "# massid predictor reference (tests/test_predictor_reference.cpp): wrenches on x86-64\n"
      "# robot predictor sample fx fy fz mx my mz, as hex floats\n";
  char buf[64];
  for (const Row& r : rows) {
    out += r.robot + " " + r.kind + " " + std::to_string(r.sample);
    for (int i = 0; i < 6; ++i) {
      std::snprintf(buf, sizeof buf, " %a", r.w[i]);
      out += buf;
    }
    out += "\n";
  }
  return out;
}

std::vector<Row> read_reference(const std::string& path) {
  std::ifstream in(path);
  if (!in) ADD_FAILURE() << "cannot read " << path;
  std::vector<Row> rows;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Row r;
    std::string v[6];
    if (!(s >> r.robot >> r.kind >> r.sample >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> v[5])) {
      ADD_FAILURE() << path << ":" << n << ": expected robot, predictor, sample and 6 numbers";
      continue;
    }
    for (int i = 0; i < 6; ++i) r.w[i] = std::strtod(v[i].c_str(), nullptr);  // hex floats
    rows.push_back(r);
  }
  return rows;
}

// Within 1 ulp of the reference, or within an absolute floor of 1e-20 (N,
// N m) where a component is near zero (a sum that cancels to nothing: its
// relative ulp says nothing of the path). The wrenches here are 0.01-100.
void expect_reference(const std::vector<Row>& got, const char* path_name) {
  const std::vector<Row> ref = read_reference(kReference);
  ASSERT_EQ(got.size(), ref.size()) << kReference << " has another number of rows";
  std::int64_t worst = 0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    const Row &g = got[k], &r = ref[k];
    ASSERT_EQ(g.robot + g.kind + std::to_string(g.sample),
              r.robot + r.kind + std::to_string(r.sample))
        << kReference << ": row " << k;
    for (int i = 0; i < 6; ++i) {
      const std::int64_t u = test::ulps(g.w[i], r.w[i]);
      if (std::abs(g.w[i] - r.w[i]) <= 1e-20) continue;
      worst = std::max(worst, u);
      EXPECT_LE(u, 1) << path_name << ": " << g.robot << " " << g.kind << " sample " << g.sample
                      << " component " << i << ": " << g.w[i] << " against " << r.w[i];
    }
  }
  std::printf("%s path: largest difference %lld ulp\n", path_name, static_cast<long long>(worst));
}

TEST(PredictorReference, TwoLanePathWithinOneUlpOfTheX86Reference) {
  const std::vector<Row> rows = predict_all(false);
  if (const char* out = std::getenv("MASSID_WRITE_REFERENCE")) {
    if (!MASSID_X86) GTEST_FAIL() << "the reference is written on x86-64";
    write_file_atomically(out, format(rows));
    std::printf("wrote %s (%zu rows)\n", out, rows.size());
    return;
  }
  expect_reference(rows, "two-lane");
}

TEST(PredictorReference, FourLanePathWithinOneUlpOfTheX86Reference) {
  if (!detail::cpu_has_avx2()) GTEST_SKIP() << "no AVX2 (an x86-64 without it, or another CPU)";
  if (std::getenv("MASSID_WRITE_REFERENCE")) GTEST_SKIP() << "writing the reference";
  expect_reference(predict_all(true), "four-lane");
}

}  // namespace
}  // namespace massid

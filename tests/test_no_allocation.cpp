// The real-time paths never allocate: a counting allocator (malloc itself,
// interposed, so that Eigen's aligned_malloc and operator new are both seen)
// around predict(), predict_motion() and the emulator's control_step().
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/emulator/controller.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "test_support.hpp"
#include "tracker_support.hpp"

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
}

namespace {
std::atomic<long> g_allocations{0};
double* volatile g_sink = nullptr;  // keeps the compiler from eliding new/delete
}  // namespace

extern "C" {
void* malloc(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
}

namespace massid {
namespace {

long allocations() { return g_allocations.load(std::memory_order_relaxed); }

TEST(CountingAllocator, SeesEigenAndOperatorNew) {
  const long before = allocations();
  {
    Eigen::VectorXd v(100);
    v.setOnes();
    EXPECT_GT(v.sum(), 0.0);
  }
  const long after_eigen = allocations();
  EXPECT_GE(after_eigen - before, 1);
  g_sink = new double[10];
  delete[] g_sink;
  EXPECT_GE(allocations() - after_eigen, 1);
}

class NoAllocation : public ::testing::TestWithParam<test::Example> {};

TEST_P(NoAllocation, PredictSingleAndBatch) {
  const Model model = load_urdf(GetParam().urdf);
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  const Predictor pred = compile_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  PredictorData data(pred);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Eigen::MatrixXd Q(64, model.num_joints()), G(64, 3), W(64, 6);
  for (Eigen::Index i = 0; i < Q.size(); ++i) Q.data()[i] = u(rng);
  for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = u(rng);
  const Eigen::VectorXd q = Q.row(0).transpose();
  const Eigen::Vector3d g = G.row(0).transpose();
  const long before = allocations();
  Wrench sum = Wrench::Zero();
  for (int k = 0; k < 100; ++k) sum += predict(pred, data, q, g);
  predict(pred, data, Q, G, W);
  EXPECT_EQ(allocations() - before, 0);
  EXPECT_TRUE(sum.allFinite());
  EXPECT_TRUE(W.allFinite());
}

TEST_P(NoAllocation, PredictMotionSingleAndBatch) {
  const Model model = load_urdf(GetParam().urdf);
  BaseParameterOptions bo;
  bo.layout = ParameterLayout::full();
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  const MotionPredictor pred =
      compile_motion_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  MotionPredictorData data(pred);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const Eigen::Index nj = model.num_joints();
  Eigen::MatrixXd Q(64, nj), Qd(64, nj), Qdd(64, nj), G(64, 3), W(64, 6);
  for (Eigen::MatrixXd* m : {&Q, &Qd, &Qdd, &G})
    for (Eigen::Index i = 0; i < m->size(); ++i) m->data()[i] = u(rng);
  const Eigen::VectorXd q = Q.row(0).transpose(), qd = Qd.row(0).transpose(),
                        qdd = Qdd.row(0).transpose();
  const Eigen::Vector3d g = G.row(0).transpose();
  FrameMotion sensor;
  sensor.omega = Eigen::Vector3d(0.1, 0.2, 0.3);
  sensor.accel = Eigen::Vector3d(1.0, 0.0, 0.5);
  const long before = allocations();
  Wrench sum = Wrench::Zero();
  for (int k = 0; k < 100; ++k)
    sum += predict_motion(pred, data, q.data(), qd.data(), qdd.data(), g, sensor);
  predict_motion(pred, data, Q, Qd, Qdd, G, W);
  EXPECT_EQ(allocations() - before, 0);
  EXPECT_TRUE(sum.allFinite());
  EXPECT_TRUE(W.allFinite());
}

// compensate's per-line path: parse, predict (static and in motion; gravity
// from gx,gy,gz and from the platform's tilt; with a clock delay, the joint
// stream's ring, grown once to the delay's span), format the output line.
TEST_P(NoAllocation, CompensateLine) {
  const Model model = load_urdf(GetParam().urdf);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (const bool motion : {false, true})
    for (const char* gravity : {"gx,gy,gz", "tilt_x_deg,tilt_y_deg"})
      for (const double delay : {0.0, 0.004}) {
        BaseParameterOptions bo;
        bo.offset = true;
        if (motion) bo.layout = ParameterLayout::full();
        const BaseParameters base = find_base_parameters(model, bo);
        std::string header = delay > 0 ? "t," : "", line;
        const int columns = model.num_joints() * (motion ? 3 : 1);
        for (int c = 0; c < columns; ++c) {
          const int j = c % std::max(model.num_joints(), 1);
          header += model.joints[j].name + (c < model.num_joints()       ? ","
                                            : c < 2 * model.num_joints() ? "_vel,"
                                                                         : "_acc,");
        }
        header += std::string(gravity) + ",fx,fy,fz,mx,my,mz";
        const int values = columns + (gravity[0] == 'g' ? 3 : 2) + 6;
        // 1 ms apart: the 4 ms delay keeps five lines in its ring.
        std::vector<std::string> lines;
        for (int i = 0; i < 120; ++i) {
          line = delay > 0 ? format_number(0.001 * i) + "," : "";
          for (int c = 0; c < values; ++c) line += (c ? "," : "") + format_number(u(rng));
          lines.push_back(line);
        }
        const IdentifiedModel identified =
            IdentifiedModel::from_values(model, base, Eigen::VectorXd::Ones(base.num_unknowns()))
                .with_delay(delay);
        Compensator comp(identified, header, "test");
        for (int k = 0; k < 20; ++k) comp.compensate(lines[k], k + 2);  // buffers and ring grown
        const long before = allocations();
        std::size_t bytes = 0;
        for (int k = 20; k < 120; ++k) bytes += comp.compensate(lines[k], k + 2).size();
        EXPECT_EQ(allocations() - before, 0)
            << (motion ? "motion, " : "static, ") << gravity << ", delay " << delay;
        EXPECT_GT(bytes, 100 * lines[0].size() / 2);
        EXPECT_TRUE(comp.compensated().allFinite());
      }
}

INSTANTIATE_TEST_SUITE_P(Examples, NoAllocation, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

// The tracker's update (tracker.hpp) over a whole tracked log: gated rows, a
// contact, two refitted changes and the restarts after them, and the
// compensate --track line with its columns.
TEST(NoAllocation, TrackerUpdateAndTrackedLine) {
  const tracker_test::TrackerLog log = tracker_test::tracker_log(true, 5);
  const IdentifiedModel identified = tracker_test::tracker_identified(log);
  Tracker tracker(identified);
  const Samples& s = log.samples;
  std::vector<Eigen::Vector3d> g(static_cast<std::size_t>(s.size()));
  std::vector<FrameMotion> sensor(g.size());
  std::vector<Wrench> w(g.size());
  for (int i = 0; i < s.size(); ++i) {
    g[static_cast<std::size_t>(i)] = s.gravity.row(i).transpose();
    const auto m = s.sensor_motion.row(i);
    sensor[static_cast<std::size_t>(i)] = {m.segment<3>(0).transpose(), m.segment<3>(3).transpose(),
                                           m.segment<3>(6).transpose()};
    w[static_cast<std::size_t>(i)] = s.wrench.row(i).transpose();
  }
  const double none = 0.0;
  int changes = 0;
  const long before = allocations();
  for (int i = 0; i < s.size(); ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    changes += tracker.update(s.time[i], &none, &none, &none, g[k], sensor[k], w[k]).event ==
               TrackerEvent::Change;
  }
  EXPECT_EQ(allocations() - before, 0);
  EXPECT_EQ(changes, 2);

  // compensate --track's line.
  const Model arm = load_urdf(test::examples()[1].urdf);
  const std::string csv = tracker_test::tracker_csv(log, arm);
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (std::size_t next; (next = csv.find('\n', at)) != std::string::npos; at = next + 1)
    lines.push_back(csv.substr(at, next - at));
  CompensatorOptions o;
  o.track = true;
  Compensator comp(identified, lines[0], "test", o);
  for (std::size_t k = 1; k < 20; ++k) comp.compensate(lines[k], static_cast<int>(k + 1));
  const long before_lines = allocations();
  for (std::size_t k = 20; k < lines.size(); ++k)
    comp.compensate(lines[k], static_cast<int>(k + 1));
  EXPECT_EQ(allocations() - before_lines, 0);
}

TEST(NoAllocation, EmulatorControlStep) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  emulator::EmulatorModel em;
  em.identified =
      IdentifiedModel::from_values(model, base, base.K * nominal_standard_parameters(model));
  em.spacecraft.mass = 50.0;
  em.spacecraft.inertia = Eigen::Vector3d(5.0, 5.0, 5.0).asDiagonal();
  emulator::EmulatorData data(em);
  const Eigen::VectorXd q = Eigen::Vector3d(0.1, -1.2, 0.9);
  Wrench measured;
  measured << 0.01, 0.02, -103.9, 0.3, -0.2, 0.0;
  const long before = allocations();
  for (int k = 0; k < 100; ++k) control_step(em, data, measured, q, data.command);
  EXPECT_EQ(allocations() - before, 0);
}

}  // namespace
}  // namespace massid

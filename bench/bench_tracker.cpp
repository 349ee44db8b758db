// Tracker::update (live/tracker.hpp), one sample per iteration, on the
// tracker tests' simulated logs of the UR-like arm (tests/tracker_support.hpp:
// 500 Hz, noise 0.05 N / 0.003 N m; 10 payload + 6 offset unknowns):
//  - rest:   the free rows at rest of a log without events;
//  - motion: the free rows in motion of the same log (the three motion
//            windows end to end: the joints are continuous across them);
//  - log:    the whole 40 s log with its events in order: rest and motion,
//            an object grasped and put down (two refitted changes), drifting
//            offsets, a two-second contact (flagged rows, refits every 4th).
// For a wrist sensor (the case: the sensor's motion given, the
// mechanism is the tool) and a base sensor (the six joints' kinematics and
// the arm's full dynamics in each update). At the end of the rows the tracker
// is rebuilt (timing paused) and the rows start again.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "massid/live/tracker.hpp"
#include "tracker_support.hpp"

namespace {

using namespace massid;
using namespace massid::tracker_test;

enum class TrackerRows { Rest, Motion, Log };

// The rows of one benchmark, contiguous per sample.
struct TrackerBenchInput {
  std::unique_ptr<IdentifiedModel> identified;
  std::vector<double> t;
  Eigen::MatrixXd q, qd, qdd;  // [num_joints x rows] (at least one row of zeros)
  std::vector<Eigen::Vector3d> gravity;
  std::vector<FrameMotion> sensor;
  std::vector<Wrench> wrench;
};

bool tracker_bench_moving(double t) {
  for (const TrackerSegment& s : kMotion)
    if (t > s.a && t < s.b) return true;
  return false;
}

const TrackerBenchInput& tracker_bench_input(bool wrist, TrackerRows kind) {
  static std::map<std::pair<bool, TrackerRows>, TrackerBenchInput> cache;
  TrackerBenchInput& in = cache[{wrist, kind}];
  if (in.identified) return in;
  const TrackerLog log = tracker_log(wrist, 1, kind == TrackerRows::Log);
  in.identified = std::make_unique<IdentifiedModel>(tracker_identified(log));
  const Samples& s = log.samples;
  std::vector<int> rows;
  for (int i = 0; i < s.size(); ++i) {
    const bool moving = tracker_bench_moving(s.time[i]);
    if (kind == TrackerRows::Log || (kind == TrackerRows::Motion) == moving) rows.push_back(i);
  }
  const int n = static_cast<int>(rows.size()), nj = static_cast<int>(s.q.cols());
  in.q.setZero(std::max(nj, 1), n);
  in.qd = in.q;
  in.qdd = in.q;
  for (int k = 0; k < n; ++k) {
    const int i = rows[static_cast<std::size_t>(k)];
    in.t.push_back(s.time[i]);
    if (nj > 0) {
      in.q.col(k).head(nj) = s.q.row(i).transpose();
      in.qd.col(k).head(nj) = s.qd.row(i).transpose();
      in.qdd.col(k).head(nj) = s.qdd.row(i).transpose();
    }
    in.gravity.push_back(s.gravity.row(i).transpose());
    FrameMotion m;
    if (s.has_sensor_motion()) {
      const auto r = s.sensor_motion.row(i);
      m = {r.segment<3>(0).transpose(), r.segment<3>(3).transpose(), r.segment<3>(6).transpose()};
    }
    in.sensor.push_back(m);
    in.wrench.push_back(s.wrench.row(i).transpose());
  }
  return in;
}

void BM_TrackerUpdate(benchmark::State& state, bool wrist, TrackerRows kind) {
  const TrackerBenchInput& in = tracker_bench_input(wrist, kind);
  auto tracker = std::make_unique<Tracker>(*in.identified);
  const std::size_t n = in.t.size();
  std::size_t i = 0;
  long long flagged = 0, changes = 0, rows = 0;
  for (auto _ : state) {
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    const TrackerEstimate& e =
        tracker->update(in.t[i], in.q.col(k).data(), in.qd.col(k).data(), in.qdd.col(k).data(),
                        in.gravity[i], in.sensor[i], in.wrench[i]);
    benchmark::DoNotOptimize(&e);
    flagged += e.event == TrackerEvent::Contact;
    changes += e.event == TrackerEvent::Change;
    ++rows;
    if (++i == n) {
      state.PauseTiming();
      tracker = std::make_unique<Tracker>(*in.identified);
      i = 0;
      state.ResumeTiming();
    }
  }
  state.counters["rows"] = static_cast<double>(n);
  state.counters["flagged_share"] = static_cast<double>(flagged) / static_cast<double>(rows);
  state.counters["changes_per_log"] =
      static_cast<double>(changes) * static_cast<double>(n) / static_cast<double>(rows);
}

BENCHMARK_CAPTURE(BM_TrackerUpdate, wrist_rest, true, TrackerRows::Rest);
BENCHMARK_CAPTURE(BM_TrackerUpdate, wrist_motion, true, TrackerRows::Motion);
BENCHMARK_CAPTURE(BM_TrackerUpdate, wrist_log, true, TrackerRows::Log);
BENCHMARK_CAPTURE(BM_TrackerUpdate, base_rest, false, TrackerRows::Rest);
BENCHMARK_CAPTURE(BM_TrackerUpdate, base_motion, false, TrackerRows::Motion);
BENCHMARK_CAPTURE(BM_TrackerUpdate, base_log, false, TrackerRows::Log);

}  // namespace

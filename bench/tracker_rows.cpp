// The tracker's side of the numpy anchor (bench/numpy_tracker.py;
// scripts/bench.sh):
//
//   massid_tracker_rows OUT   (writes OUT.json and OUT.bin)
//
// On the tracker tests' 40 s wrist log (tests/tracker_support.hpp, seed 1:
// the UR-like arm moving and at rest, an object grasped and put down, drifting
// offsets, a contact; 20 000 rows at 500 Hz) it
//  - times Tracker::update per row, the tracker as `compensate --track` runs
//    it (default options: the gate, the lag, the refits, the projection, the
//    kinematics and the mechanism's prediction), and as a plain Kalman filter
//    (lag 0, no gate: every row learnt as it comes), best of 5 passes; and
//    the part of it that forms the rows (the kinematics, LINK's regressor,
//    the mechanism's prediction: what the anchor is given);
//  - writes each row's inputs to the filter, formed as the tracker forms them
//    (z = measured - predicted mechanism, Y = LINK's regressor), to OUT.bin:
//    per row t, Y (6 x 10, row-major), z (6), little-endian doubles;
//  - writes OUT.json: the rows' count, the filter's start (x0, P0), the noise's
//    and the random walk's variances, the plain filter's final state and
//    covariance (which the anchor must reproduce from OUT.bin: the rows are
//    the tracker's own), and the times.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "massid/core/regressor.hpp"
#include "massid/live/tracker.hpp"
#include "tracker_support.hpp"

namespace {

using namespace massid;

std::string json_array(const double* v, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) out += fmt::format("{}{:.17g}", i ? ", " : "", v[i]);
  return out + "]";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: massid_tracker_rows OUT  (writes OUT.json, OUT.bin)\n");
    return 2;
  }
  const std::string out = argv[1];
  const tracker_test::TrackerLog log = tracker_test::tracker_log(true, 1);
  const IdentifiedModel model = tracker_test::tracker_identified(log);
  const Samples& s = log.samples;
  const int n = s.size();
  std::vector<Eigen::Vector3d> g(static_cast<std::size_t>(n));
  std::vector<FrameMotion> sensor(g.size());
  std::vector<Wrench> w(g.size());
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    g[k] = s.gravity.row(i).transpose();
    const auto m = s.sensor_motion.row(i);
    sensor[k] = {m.segment<3>(0).transpose(), m.segment<3>(3).transpose(),
                 m.segment<3>(6).transpose()};
    w[k] = s.wrench.row(i).transpose();
  }
  const double none = 0.0;  // the wrist model has no joints
  TrackerOptions plain;
  plain.lag = 0;
  plain.gate = 1e300;

  // ns per row, best of 5 passes over the log, each with a new tracker.
  const auto time_rows = [&](const TrackerOptions& options) {
    double best = 1e300;
    for (int pass = 0; pass < 5; ++pass) {
      Tracker tracker(model, options);
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < n; ++i) {
        const std::size_t k = static_cast<std::size_t>(i);
        tracker.update(s.time[i], &none, &none, &none, g[k], sensor[k], w[k]);
      }
      const double ns =
          std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
      best = std::min(best, ns / n);
    }
    return best;
  };
  const double full_ns = time_rows(TrackerOptions{});
  const double plain_ns = time_rows(plain);

  // The part of it that forms the rows (the mechanism's prediction, the
  // kinematics, LINK's regressor), which the anchor is given: the same
  // calls as the tracker's, best of 5 passes.
  IdentifiedModelData data(model);
  KinematicsData kin(model.model());
  const Eigen::VectorXd empty(0);
  const int link = Tracker(model).payload_link();
  // A tool rigid on the sensor (a dynamic model with no joints: this log's)
  // is predicted by the tracker as one body on LINK, Y theta with theta
  // fitted once (Tracker::Impl::rigid_mechanism): the product costs what it
  // costs whatever theta holds.
  const bool rigid = model.dynamic() && model.num_joints() == 0;
  const Eigen::Matrix<double, 10, 1> theta = Eigen::Matrix<double, 10, 1>::Constant(0.1);
  double rows_ns = 1e300, sink = 0.0;
  for (int pass = 0; pass < 5; ++pass) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      forward_kinematics(model.model(), kin, empty, empty, empty, g[k], sensor[k]);
      const Eigen::Matrix<double, 6, 10> Y = link_regressor(kin, link);
      const Wrench z = w[k] - (rigid ? Wrench(Y * theta)
                                     : model.predict(data, &none, &none, &none, g[k], sensor[k]));
      sink += z[0] + Y(5, 9);
    }
    const double ns =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    rows_ns = std::min(rows_ns, ns / n);
  }

  // The rows, and the plain filter's run over them.
  Tracker tracker(model, plain);
  const Eigen::Matrix<double, 16, 1> x0 = tracker.state();
  const Eigen::Matrix<double, 16, 16> P0 = tracker.covariance();
  std::vector<double> rows;
  rows.reserve(static_cast<std::size_t>(n) * 67);
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    tracker.update(s.time[i], &none, &none, &none, g[k], sensor[k], w[k]);
    forward_kinematics(model.model(), kin, empty, empty, empty, g[k], sensor[k]);
    const Eigen::Matrix<double, 6, 10> Y = link_regressor(kin, tracker.payload_link());
    const Wrench z = w[k] - model.predict(data, &none, &none, &none, g[k], sensor[k]);
    rows.push_back(s.time[i]);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 10; ++c) rows.push_back(Y(r, c));
    for (int r = 0; r < 6; ++r) rows.push_back(z[r]);
  }
  std::FILE* bin = std::fopen((out + ".bin").c_str(), "wb");
  if (!bin || std::fwrite(rows.data(), sizeof(double), rows.size(), bin) != rows.size()) {
    std::fprintf(stderr, "massid_tracker_rows: cannot write %s.bin\n", out.c_str());
    return 1;
  }
  std::fclose(bin);
  const TrackerOptions o;
  const Wrench noise = o.noise.cwiseAbs2(), walk = o.offset_walk.cwiseAbs2();
  const Eigen::Matrix<double, 16, 1> x = tracker.state();
  const Eigen::Matrix<double, 16, 16> P = tracker.covariance();
  std::FILE* json = std::fopen((out + ".json").c_str(), "w");
  if (!json) {
    std::fprintf(stderr, "massid_tracker_rows: cannot write %s.json\n", out.c_str());
    return 1;
  }
  std::fprintf(
      json, "%s",
      fmt::format("{{\n  \"rows\": {},\n  \"row_doubles\": 67,\n  \"x0\": {},\n"
                  "  \"P0\": {},\n  \"noise_var\": {},\n  \"walk_var\": {},\n"
                  "  \"x_final\": {},\n  \"P_final\": {},\n"
                  "  \"massid_ns_per_row\": {:.4g},\n"
                  "  \"massid_plain_ns_per_row\": {:.4g},\n"
                  "  \"massid_row_forming_ns_per_row\": {:.4g}\n}}\n",
                  n, json_array(x0.data(), 16), json_array(P0.data(), 256),
                  json_array(noise.data(), 6), json_array(walk.data(), 6), json_array(x.data(), 16),
                  json_array(P.data(), 256), full_ns, plain_ns, rows_ns)
          .c_str());
  std::fclose(json);
  std::printf(
      "massid Tracker::update, %d rows of the tracked wrist log (10 + 6 unknowns): %.0f ns "
      "per row (as compensate --track runs it), %.0f ns as a plain Kalman filter; forming the "
      "rows alone %.0f ns%s\n",
      n, full_ns, plain_ns, rows_ns, sink == 0.0 ? " " : "");
  return 0;
}

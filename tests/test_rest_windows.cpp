// Rest windows of continuous static logs (rest_windows.hpp): one log of a
// robot moving from pose to pose (quintic moves, the platform tilting between
// the plan's gravity directions, the wrench of the motion itself from the
// dynamic simulation, a damped ringing after each stop, sensor noise). The
// windows are the rests the timeline was built with; the fit on them matches
// the URDF's base parameters within 4 std, while every row (the transitions)
// biases it far beyond; plan-like logs are left alone.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>

#include "identify/identify_file.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/rest_windows.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

struct Timeline {
  Samples log;                 // t, q, qd, qdd, gravity, wrench
  std::vector<double> stops;   // times each move ends (the rest after it begins)
  std::vector<double> starts;  // times each move begins
  int poses = 0;
};

// How the log is recorded. The defaults: rests of 2 s, quintic moves of
// 1.5 s, a ring of `ring` N on fx (and 0.2 ring N m on my) at 6 Hz decaying
// in 0.1 s after each stop, white noise, no sensor filter.
struct Shape {
  double rate = 500.0;                    // Hz
  double rest_min = 2.0, rest_max = 2.0;  // s: each rest drawn uniformly in [min, max]
  double move_min = 1.5, move_max = 1.5;  // s: each move's duration
  bool cubic = false;  // cubic moves (the acceleration jumps at both ends), else quintic
  // Ringing after each stop. Fixed: `ring` N on fx, 0.2 `ring` N m on my,
  // sin(2 pi ring_hz t) exp(-t / ring_decay). Excited (`ring_gain` > 0): the
  // structure's response to the stop's step in the dynamic wrench, that step
  // times ring_gain exp(-t / tau) cos(2 pi f t), f in [ring_hz_min,
  // ring_hz_max] and tau in [decay_min, decay_max] drawn per stop.
  double ring = 0.0, ring_hz = 6.0, ring_decay = 0.1;
  double ring_amplitude = 0.0;  // N (N m: a tenth), in a random direction per stop
  double ring_gain = 0.0, ring_hz_min = 5.0, ring_hz_max = 15.0, decay_min = 0.1, decay_max = 0.1;
  double sensor_lag = 0.0;  // s: the sensor's first-order low-pass, before the noise
  std::uint64_t seed = 11;
};

// The plan's poses in order, resting at each and moving between them
// (zero velocity at both ends).
Timeline continuous_log(const Model& model, const Samples& plan, int poses, double ring,
                        bool joints_move = true, Shape shape = {}) {
  if (ring > 0.0) shape.ring = ring;
  Timeline tl;
  tl.poses = poses;
  const int nj = model.num_joints();
  const double rate = shape.rate;
  std::mt19937_64 rng(shape.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto draw = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  std::vector<int> rest_rows, move_rows;
  int n = 0;
  for (int p = 0; p < poses; ++p) {
    rest_rows.push_back(static_cast<int>(std::lround(draw(shape.rest_min, shape.rest_max) * rate)));
    n += rest_rows.back();
    if (p + 1 == poses) break;
    move_rows.push_back(static_cast<int>(std::lround(draw(shape.move_min, shape.move_max) * rate)));
    n += move_rows.back();
  }
  Samples& s = tl.log;
  s.time.resize(n);
  s.q.resize(n, nj);
  s.qd.setZero(n, nj);
  s.qdd.setZero(n, nj);
  s.gravity.resize(n, 3);
  std::vector<int> stop_rows;
  int row = 0;
  for (int p = 0; p < poses; ++p) {
    const Eigen::VectorXd qa = plan.q.row(joints_move ? p : 0).transpose();
    for (int r = 0; r < rest_rows[p]; ++r, ++row) {
      s.time[row] = row / rate;
      s.q.row(row) = qa.transpose();
      s.gravity.row(row) = plan.gravity.row(p);
    }
    if (p + 1 == poses) break;
    tl.starts.push_back(row / rate);
    const Eigen::VectorXd dq = (plan.q.row(joints_move ? p + 1 : 0).transpose() - qa);
    const Eigen::Vector3d ga = plan.gravity.row(p).transpose(),
                          gb = plan.gravity.row(p + 1).transpose();
    const int m = move_rows[p];
    const double T = m / rate;
    for (int r = 0; r < m; ++r, ++row) {
      const double u = (r + 1.0) / m;  // ends at the next pose
      double sp, v, a;
      if (shape.cubic) {
        sp = u * u * (3 - 2 * u);
        v = 6 * u * (1 - u) / T;
        a = r + 1 == m ? 0.0 : 6 * (1 - 2 * u) / (T * T);  // at rest on the last row
      } else {
        sp = u * u * u * (10 - 15 * u + 6 * u * u);
        v = 30 * u * u * (1 - u) * (1 - u) / T;
        a = 60 * u * (1 - u) * (1 - 2 * u) / (T * T);
      }
      s.time[row] = row / rate;
      s.q.row(row) = (qa + sp * dq).transpose();
      s.qd.row(row) = (v * dq).transpose();
      s.qdd.row(row) = (a * dq).transpose();
      s.gravity.row(row) = (((1 - sp) * ga + sp * gb).normalized() * ga.norm()).transpose();
    }
    tl.stops.push_back(row / rate);
    stop_rows.push_back(row - 1);  // the last row of the move: at the next pose, at rest
  }
  SimulateOptions so;
  so.dynamic = true;
  const bool filtered = shape.sensor_lag > 0.0;
  if (!filtered) {
    so.noise_force = 0.05;
    so.noise_moment = 0.005;
    so.seed = shape.seed;
  }
  s.wrench = simulate_wrenches(model, s, so);
  const Eigen::MatrixXd ideal = s.wrench;
  for (std::size_t k = 0; k < tl.stops.size(); ++k) {
    const double f = draw(shape.ring_hz_min, shape.ring_hz_max),
                 tau = draw(shape.decay_min, shape.decay_max);
    // The step of the dynamic wrench at the stop (cubic: the deceleration ends at once).
    const Wrench step = (ideal.row(stop_rows[k] - 1) - ideal.row(stop_rows[k])).transpose();
    Wrench direction;
    for (int c = 0; c < 6; ++c) direction[c] = (c < 3 ? 1.0 : 0.1) * (2 * unit(rng) - 1);
    const double phase =
        shape.ring_gain > 0.0 ? std::numbers::pi / 2 : 2 * std::numbers::pi * unit(rng);
    for (int i = stop_rows[k]; i < n; ++i) {
      const double dt = s.time[i] - tl.stops[k];
      if (dt > 3.0) break;
      if (shape.ring > 0.0 && dt >= 0.0 && dt <= 1.0) {
        const double r = shape.ring * std::exp(-dt / shape.ring_decay) *
                         std::sin(2 * std::numbers::pi * shape.ring_hz * dt);
        s.wrench(i, 0) += r;
        s.wrench(i, 4) += 0.2 * r;
      }
      const double since = s.time[i] - s.time[stop_rows[k]];  // from the last row of the move
      if (shape.ring_gain > 0.0 || shape.ring_amplitude > 0.0)
        s.wrench.row(i) += std::exp(-since / tau) *
                           std::sin(2 * std::numbers::pi * f * since + phase) *
                           (shape.ring_gain * step + shape.ring_amplitude * direction).transpose();
    }
  }
  if (filtered) {
    // The sensor's own filter: first order, then white noise of the converter.
    const double alpha = 1.0 - std::exp(-1.0 / (rate * shape.sensor_lag));
    for (int i = 1; i < n; ++i)
      s.wrench.row(i) = s.wrench.row(i - 1) + alpha * (s.wrench.row(i) - s.wrench.row(i - 1));
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 6; ++c) s.wrench(i, c) += (c < 3 ? 0.05 : 0.005) * noise(rng);
  }
  s.line.resize(n);
  for (int i = 0; i < n; ++i) s.line[i] = i + 2;
  return tl;
}

Samples static_part(const Samples& s) {
  Samples out = s;
  out.qd.resize(0, 0);
  out.qdd.resize(0, 0);
  return out;
}

TEST(RestWindows, FoundWhereTheRobotRestedAndTheFitIsUnbiased) {
  const test::Example ex = test::examples()[1];  // ur_like, a tilting plan
  const Model model = load_urdf(ex.urdf);
  const Samples plan = test::load_plan(model, ex.plan);
  const int poses = std::min(20, plan.size());
  const Timeline tl = continuous_log(model, plan, poses, 3.0);
  const Samples log = static_part(tl.log);

  const RestWindows w = find_rest_windows(log);
  ASSERT_TRUE(w.continuous);
  ASSERT_EQ(static_cast<int>(w.windows.size()), poses);
  EXPECT_EQ(w.rows, log.size());
  EXPECT_NE(w.criterion.find("joints"), std::string::npos);
  for (int p = 0; p < poses; ++p) {
    // Each window lies inside its rest: after the stop (and the settling) and
    // before the next start, and covers most of it.
    const double t0 = log.time[w.windows[p].first], t1 = log.time[w.windows[p].last];
    const double rest_begin = p == 0 ? 0.0 : tl.stops[p - 1];
    const double rest_end = p + 1 == poses ? log.time[log.size() - 1] : tl.starts[p];
    EXPECT_GE(t0, rest_begin + (p == 0 ? 0.0 : 0.2)) << "window " << p;
    EXPECT_LE(t1, rest_end) << "window " << p;
    EXPECT_GT(t1 - t0, 0.75 * (rest_end - rest_begin) - 0.3) << "window " << p;
  }
  int inside = 0;
  for (const RestWindow& win : w.windows) inside += win.last - win.first + 1;
  EXPECT_EQ(inside, w.samples);

  BaseParameterOptions bo;
  const BaseParameters base = find_base_parameters(model, bo);
  const Samples rest = rest_samples(log, w);
  ASSERT_EQ(rest.size(), w.samples);
  EXPECT_EQ(rest.line.front(), log.line[w.windows.front().first]);
  const IdentifySummary fit = identify(model, base, rest);
  EXPECT_LT(test::worst_normalised_error(model, base, fit), 4.0);
  // Every row, transitions included: the motion's forces bias the fit.
  const IdentifySummary all = identify(model, base, log);
  EXPECT_GT(test::worst_normalised_error(model, base, all), 20.0);
}

TEST(RestWindows, PlanLikeLogsAreLeftAlone) {
  const test::Example ex = test::examples()[1];
  const Model model = load_urdf(ex.urdf);
  Samples plan = test::load_plan(model, ex.plan);
  plan.wrench = simulate_wrenches(model, plan);
  // One row per pose at 1 Hz: a set of poses.
  plan.time = Eigen::VectorXd::LinSpaced(plan.size(), 0.0, plan.size() - 1.0);
  EXPECT_FALSE(find_rest_windows(plan).continuous);
  // 200 rows per pose at 100 Hz, the pose changing from one row to the next:
  // no row lies between two poses.
  const int repeat = 200;
  Samples held;
  held.q.resize(plan.size() * repeat, plan.q.cols());
  held.gravity.resize(plan.size() * repeat, 3);
  for (int i = 0; i < held.q.rows(); ++i) {
    held.q.row(i) = plan.q.row(i / repeat);
    held.gravity.row(i) = plan.gravity.row(i / repeat);
  }
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  held.wrench = simulate_wrenches(model, held, so);
  held.time = Eigen::VectorXd::LinSpaced(held.q.rows(), 0.0, (held.q.rows() - 1) / 100.0);
  const RestWindows w = find_rest_windows(held);
  EXPECT_FALSE(w.continuous) << w.moving << " moving rows by " << w.criterion;
  EXPECT_EQ(w.samples, held.size());
  // A bump (a cable touched for a moment) while nothing moves: the outlier
  // test's business, the log stays whole.
  for (int i = 500; i < 503; ++i) held.wrench(i, 0) += 5.0;
  EXPECT_FALSE(find_rest_windows(held).continuous);
  // Off: every row, whatever the log.
  const Timeline tl = continuous_log(model, plan, 4, 0.0);
  RestWindowOptions off;
  off.detection = RestDetection::Off;
  EXPECT_FALSE(find_rest_windows(static_part(tl.log), off).continuous);
  EXPECT_TRUE(find_rest_windows(static_part(tl.log)).continuous);
}

TEST(RestWindows, TheWrenchShowsATiltWhenTheJointsStayAndGravityComesFromTheForce) {
  const test::Example ex = test::examples()[1];
  const Model model = load_urdf(ex.urdf);
  const Samples plan = test::load_plan(model, ex.plan);
  const Timeline tl = continuous_log(model, plan, 6, 0.0, /*joints_move=*/false);
  Samples log = static_part(tl.log);
  // No gx,gy,gz columns: gravity along the measured force (eq. 37).
  log.gravity_from_force = true;
  for (int i = 0; i < log.size(); ++i)
    log.gravity.row(i) = kStandardGravity * log.wrench.row(i).head<3>().normalized();
  const RestWindows w = find_rest_windows(log);
  ASSERT_TRUE(w.continuous);
  EXPECT_EQ(w.criterion, "wrench");
  // Consecutive plan poses may share a tilt: then there was no motion between them.
  int tilts = 1;
  for (int p = 1; p < 6; ++p)
    tilts += (plan.gravity.row(p) - plan.gravity.row(p - 1)).norm() > 1e-6;
  EXPECT_EQ(static_cast<int>(w.windows.size()), tilts);
}

TEST(RestWindows, IdentifyFileUsesTheWindowsOfAContinuousCsv) {
  const test::Example ex = test::examples()[1];
  const Model model = load_urdf(ex.urdf);
  const Samples plan = test::load_plan(model, ex.plan);
  const Timeline tl = continuous_log(model, plan, 12, 3.0);
  const Samples& s = tl.log;
  std::vector<std::string> header{"t"};
  for (const Joint& j : model.joints) header.push_back(j.name);
  for (const char* c : {"gx", "gy", "gz"}) header.push_back(c);
  for (const char* c : kWrenchColumns) header.push_back(c);
  std::vector<std::vector<std::string>> rows(s.size());
  for (int i = 0; i < s.size(); ++i) {
    rows[i].push_back(format_number(s.time[i]));
    for (int j = 0; j < s.q.cols(); ++j) rows[i].push_back(format_number(s.q(i, j)));
    for (int k = 0; k < 3; ++k) rows[i].push_back(format_number(s.gravity(i, k)));
    for (int k = 0; k < 6; ++k) rows[i].push_back(format_number(s.wrench(i, k)));
  }
  const auto path = (std::filesystem::temp_directory_path() / "massid_continuous.csv").string();
  write_csv(path, header, rows);

  const BaseParameters base = find_base_parameters(model, {});
  Samples used;
  const IdentifySummary fit = identify_file(model, base, path, {}, &used);
  ASSERT_TRUE(fit.rest.continuous);
  EXPECT_EQ(static_cast<int>(fit.rest.windows.size()), 12);
  EXPECT_EQ(fit.samples, fit.rest.samples);
  EXPECT_EQ(used.size(), fit.samples);
  // The same windows and fit as on the samples in memory.
  const Samples all = read_samples(model, read_csv(path), WrenchColumns::Required);
  const RestWindows w = find_rest_windows(all);
  EXPECT_EQ(w.samples, fit.rest.samples);
  const IdentifySummary dense = identify(model, base, rest_samples(all, w));
  EXPECT_EQ(dense.value, fit.value);
  EXPECT_LT(test::worst_normalised_error(model, base, fit), 4.0);
  IdentifyOptions off;
  off.rest.detection = RestDetection::Off;
  const IdentifySummary every = identify_file(model, base, path, off);
  EXPECT_FALSE(every.rest.continuous);
  EXPECT_EQ(every.samples, s.size());
  std::filesystem::remove(path);
}

// A log shaped like a lab's (issue 26): 40 holds of 1.5-3 s joined by fast
// moves of 0.5-1 s (cubic: the acceleration jumps at both ends), 500 Hz; after
// each stop the structure rings (5-15 Hz, 0.2-0.4 s time constant, 0.2 N in a
// random direction), and the sensor's own first-order filter (80 ms: a
// 2 Hz low-pass) makes the wrench catch up slowly after each move.
// The windows the motion alone gives (trim off) leave the filter's tail in:
// a fit many std off. Trimmed where the data show the wrench has not
// settled, every base parameter lies within 4 std of the URDF's.
TEST(RestWindows, SettlingAfterEachMoveIsTrimmedAsTheDataShow) {
  const test::Example ex = test::examples()[1];  // ur_like, a tilting plan
  const Model model = load_urdf(ex.urdf);
  const Samples plan = test::load_plan(model, ex.plan);
  const BaseParameters base = find_base_parameters(model, {});
  Shape sh;
  sh.rest_min = 1.5;
  sh.rest_max = 3.0;
  sh.move_min = 0.5;
  sh.move_max = 1.0;
  sh.cubic = true;
  sh.ring_amplitude = 0.2;
  sh.decay_min = 0.2;
  sh.decay_max = 0.4;
  sh.sensor_lag = 0.08;
  const Timeline tl = continuous_log(model, plan, 40, 0.0, true, sh);
  const Samples log = static_part(tl.log);

  RestWindowOptions plain;
  plain.trim = false;
  const RestWindows untrimmed = find_rest_windows(log, plain);
  ASSERT_EQ(static_cast<int>(untrimmed.windows.size()), 40);
  EXPECT_EQ(untrimmed.trimmed, 0);
  const IdentifySummary biased = identify(model, base, rest_samples(log, untrimmed));
  EXPECT_GT(test::worst_normalised_error(model, base, biased), 5.0);

  const RestWindows w = find_rest_windows(log);
  ASSERT_TRUE(w.continuous);
  ASSERT_EQ(static_cast<int>(w.windows.size()), 40);
  // The trimmed windows lie inside the plain ones; the rows cut are counted.
  int inside = 0;
  for (std::size_t k = 0; k < w.windows.size(); ++k) {
    EXPECT_GE(w.windows[k].first, untrimmed.windows[k].first) << "window " << k;
    EXPECT_LE(w.windows[k].last, untrimmed.windows[k].last) << "window " << k;
    inside += w.windows[k].last - w.windows[k].first + 1;
  }
  EXPECT_EQ(inside, w.samples);
  EXPECT_EQ(w.samples + w.trimmed, untrimmed.samples);
  EXPECT_GT(w.trimmed, 0);
  // The filter's tail after a stop: exp(-t / 80 ms) of the step in the wrench
  // falls to the noise in a few tenths of a second.
  EXPECT_GT(w.longest_settling, 0.1);
  EXPECT_LT(w.longest_settling, 1.5);
  const IdentifySummary fit = identify(model, base, rest_samples(log, w));
  EXPECT_LT(test::worst_normalised_error(model, base, fit), 4.0);
  std::printf("untrimmed worst %.2f std; trimmed %d rows (longest %.3f s), worst %.2f std\n",
              test::worst_normalised_error(model, base, biased), w.trimmed, w.longest_settling,
              test::worst_normalised_error(model, base, fit));
}

// Issue 29: a wrist sensor on an arm that moves slowly and without pause
// (`slow`: every joint a sine of at most 0.1 rad/s, no rest at all), or
// that holds poses with fast moves between them (quintic moves of about 1
// rad in 0.8 s). The wrench is the dynamic simulation's (the motion's own
// forces included) with noise of 0.1 N and 0.01 N m; the static log keeps
// the arm's positions, t and the wrench.
Samples quasi_static_wrist_log(const Model& wrist, bool slow) {
  const int nu = wrist.num_upstream_joints();
  const double rate = 100.0;
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::MatrixXd q, qd, qdd;
  if (slow) {
    const int n = 6000;  // 60 s
    q.resize(n, nu), qd.resize(n, nu), qdd.resize(n, nu);
    for (int j = 0; j < nu; ++j) {
      const double w = 0.11 + 0.04 * j, amplitude = 0.1 / w, phase = 3 * unit(rng),
                   centre = 0.8 * unit(rng);
      for (int i = 0; i < n; ++i) {
        const double t = i / rate;
        q(i, j) = centre + amplitude * std::sin(w * t + phase);
        qd(i, j) = amplitude * w * std::cos(w * t + phase);
        qdd(i, j) = -amplitude * w * w * std::sin(w * t + phase);
      }
    }
  } else {
    const int poses = 12, hold = 200, move = 80;
    const int n = poses * hold + (poses - 1) * move;
    q.resize(n, nu), qd.setZero(n, nu), qdd.setZero(n, nu);
    Eigen::VectorXd qa(nu);
    for (int j = 0; j < nu; ++j) qa[j] = 1.2 * unit(rng);
    int row = 0;
    for (int p = 0; p < poses; ++p) {
      for (int r = 0; r < hold; ++r, ++row) q.row(row) = qa.transpose();
      if (p + 1 == poses) break;
      Eigen::VectorXd dq(nu);
      for (int j = 0; j < nu; ++j) dq[j] = unit(rng);
      const double T = move / rate;
      for (int r = 0; r < move; ++r, ++row) {
        const double u = (r + 1.0) / move;
        q.row(row) = (qa + u * u * u * (10 - 15 * u + 6 * u * u) * dq).transpose();
        qd.row(row) = (30 * u * u * (1 - u) * (1 - u) / T * dq).transpose();
        qdd.row(row) = (60 * u * (1 - u) * (1 - 2 * u) / (T * T) * dq).transpose();
      }
      qa += dq;
    }
  }
  const int n = static_cast<int>(q.rows());
  Samples s;
  s.q.resize(n, 0);
  s.q_upstream = q;
  s.qd_upstream = qd;
  s.qdd_upstream = qdd;
  s.gravity.resize(n, 3);
  s.gravity_from_upstream = true;
  resolve_upstream(wrist, s);  // gravity and the sensor frame's motion from the arm
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  so.seed = 29;
  s.wrench = simulate_wrenches(wrist, s, so);
  // The static log: positions, t and the wrench (gravity from the arm's joints).
  s.qd_upstream.resize(0, 0);
  s.qdd_upstream.resize(0, 0);
  s.sensor_motion.resize(0, 0);
  s.time.resize(n);
  s.line.resize(n);
  for (int i = 0; i < n; ++i) {
    s.time[i] = i / rate;
    s.line[i] = i + 2;
  }
  return s;
}

TEST(RestWindows, ASlowContinuousLogIsQuasiStaticAndEveryRowIsASample) {
  const Model wrist = load_urdf(test::kUrLikeUrdf, "wrist_3_link");
  const Samples log = quasi_static_wrist_log(wrist, true);
  double fastest = 0.0;
  for (int i = 1; i < log.size(); ++i)
    fastest = std::max(fastest,
                       (log.q_upstream.row(i) - log.q_upstream.row(i - 1)).cwiseAbs().maxCoeff() /
                           (log.time[i] - log.time[i - 1]));
  ASSERT_LE(fastest, 0.1);
  ASSERT_GT(fastest, 0.09);
  // The windows alone find the slow motion (the gravity turns) and would cut the log.
  const RestWindows windows = find_rest_windows(log);
  ASSERT_TRUE(windows.continuous);
  ASSERT_LT(windows.samples, log.size() / 2);
  // With the model: quasi-static, every row, the numbers that justify it.
  const RestWindows w = find_rest_windows(wrist, log);
  EXPECT_TRUE(w.quasi_static);
  EXPECT_FALSE(w.continuous);
  EXPECT_EQ(w.samples, log.size());
  EXPECT_EQ(w.windowed_samples, windows.samples);
  EXPECT_NEAR(w.max_speed, fastest, 0.01);
  EXPECT_NEAR(w.noise_force, 0.1, 0.02);
  EXPECT_NEAR(w.noise_moment, 0.01, 0.002);
  EXPECT_GT(w.inertial_force, 0.0);
  EXPECT_LT(w.inertial_force, 0.25 * w.noise_force);
  EXPECT_LT(w.inertial_moment, 0.25 * w.noise_moment);

  // identify's default (rest auto) uses every row and agrees with rest off.
  IdentifyRequest r;
  r.offset = true;
  const Identification auto_rest = identify(wrist, r, IdentifySource::data(log));
  r.rest = "off";
  const Identification off = identify(wrist, r, IdentifySource::data(log));
  EXPECT_EQ(auto_rest.summary.samples, log.size());
  EXPECT_TRUE(auto_rest.summary.rest.quasi_static);
  const int m = auto_rest.base.total_mass;
  ASSERT_GE(m, 0);
  for (int i = 0; i < off.summary.value.size(); ++i)
    EXPECT_LE(std::abs(auto_rest.summary.value[i] - off.summary.value[i]), off.summary.stddev[i])
        << i;
  EXPECT_NEAR(auto_rest.summary.value[m], wrist.nominal_total_mass(),
              4 * auto_rest.summary.stddev[m]);
  EXPECT_LT(test::worst_normalised_error(wrist, auto_rest.base, auto_rest.summary), 4.0);
  const std::string report = identify_report(wrist, auto_rest.base, auto_rest.summary, "log");
  EXPECT_NE(report.find(fmt::format("quasi-static throughout: the joints move at most {:.3g} rad/s",
                                    w.max_speed)),
            std::string::npos)
      << report;
  EXPECT_NE(report.find(fmt::format("all {} rows used", log.size())), std::string::npos) << report;
}

TEST(RestWindows, FastMovesBetweenHoldsStillUseTheWindows) {
  const Model wrist = load_urdf(test::kUrLikeUrdf, "wrist_3_link");
  const Samples log = quasi_static_wrist_log(wrist, false);
  const RestWindows w = find_rest_windows(wrist, log);
  ASSERT_TRUE(w.continuous);
  EXPECT_FALSE(w.quasi_static);
  EXPECT_TRUE(w.inertia_checked);
  EXPECT_GT(w.inertial_force, 0.25 * w.noise_force);
  EXPECT_EQ(static_cast<int>(w.windows.size()), 12);
  EXPECT_EQ(w.samples, find_rest_windows(log).samples);  // the windows as without the model
  IdentifyRequest r;
  r.offset = true;
  const Identification id = identify(wrist, r, IdentifySource::data(log));
  EXPECT_EQ(id.summary.samples, w.samples);
  EXPECT_FALSE(id.summary.rest.quasi_static);
  EXPECT_LT(test::worst_normalised_error(wrist, id.base, id.summary), 4.0);
}

}  // namespace
}  // namespace massid

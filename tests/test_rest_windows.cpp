// Rest windows of continuous static logs (rest_windows.hpp): one log of a
// robot moving from pose to pose (quintic moves, the platform tilting between
// the plan's gravity directions, the wrench of the motion itself from the
// dynamic simulation, a damped ringing after each stop, sensor noise). The
// windows are the rests the timeline was built with; the fit on them matches
// the URDF's base parameters within 4 std, while every row (the transitions)
// biases it far beyond; plan-like logs are left alone.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>

#include "identify/identify_file.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/rest_windows.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

struct Timeline {
  Samples log;                 // t, q, qd, qdd, gravity, wrench
  std::vector<double> stops;   // times each move ends (the rest after it begins)
  std::vector<double> starts;  // times each move begins
  int poses = 0;
};

constexpr double kRate = 500.0, kRest = 2.0, kMove = 1.5;

// The plan's poses in order, resting kRest at each and moving kMove between
// them along a quintic (zero velocity and acceleration at both ends).
Timeline continuous_log(const Model& model, const Samples& plan, int poses, double ring,
                        bool joints_move = true) {
  Timeline tl;
  tl.poses = poses;
  const int nj = model.num_joints();
  const int rest_rows = static_cast<int>(kRest * kRate),
            move_rows = static_cast<int>(kMove * kRate);
  const int n = poses * rest_rows + (poses - 1) * move_rows;
  Samples& s = tl.log;
  s.time.resize(n);
  s.q.resize(n, nj);
  s.qd.setZero(n, nj);
  s.qdd.setZero(n, nj);
  s.gravity.resize(n, 3);
  int row = 0;
  for (int p = 0; p < poses; ++p) {
    const Eigen::VectorXd qa = plan.q.row(joints_move ? p : 0).transpose();
    for (int r = 0; r < rest_rows; ++r, ++row) {
      s.time[row] = row / kRate;
      s.q.row(row) = qa.transpose();
      s.gravity.row(row) = plan.gravity.row(p);
    }
    if (p + 1 == poses) break;
    tl.starts.push_back(row / kRate);
    const Eigen::VectorXd dq = (plan.q.row(joints_move ? p + 1 : 0).transpose() - qa);
    const Eigen::Vector3d ga = plan.gravity.row(p).transpose(),
                          gb = plan.gravity.row(p + 1).transpose();
    for (int r = 0; r < move_rows; ++r, ++row) {
      const double u = (r + 1.0) / move_rows;  // ends at the next pose
      const double sp = u * u * u * (10 - 15 * u + 6 * u * u);
      const double v = 30 * u * u * (1 - u) * (1 - u) / kMove;
      const double a = 60 * u * (1 - u) * (1 - 2 * u) / (kMove * kMove);
      s.time[row] = row / kRate;
      s.q.row(row) = (qa + sp * dq).transpose();
      s.qd.row(row) = (v * dq).transpose();
      s.qdd.row(row) = (a * dq).transpose();
      s.gravity.row(row) = (((1 - sp) * ga + sp * gb).normalized() * ga.norm()).transpose();
    }
    tl.stops.push_back(row / kRate);
  }
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.seed = 11;
  s.wrench = simulate_wrenches(model, s, so);
  // The mechanism rings after each stop: 6 Hz, decaying in 0.1 s.
  for (double stop : tl.stops)
    for (int i = 0; i < n; ++i) {
      const double dt = s.time[i] - stop;
      if (dt < 0 || dt > 1.0) continue;
      const double r = ring * std::exp(-dt / 0.1) * std::sin(2 * std::numbers::pi * 6.0 * dt);
      s.wrench(i, 0) += r;
      s.wrench(i, 4) += 0.2 * r;
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

}  // namespace
}  // namespace massid

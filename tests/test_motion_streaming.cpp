// Streaming identification in motion (streaming.hpp) against the in-memory
// path (identify() of read_motion_samples, the base of motion_base_options):
// values, standard deviations, covariance and every other figure agree to
// 1e-9 relative, whether the log gives the velocities or they are derived by
// the filter in the stream (blocks much shorter than the filter window, every
// decimation phase), with offsets or not, with joints above the sensor link,
// with a block column; the result does not depend on the number of threads;
// what the head of a file suggests and the file contradicts (gravity that
// starts level, then tilts; a sensor that starts still) is found and
// corrected, and the sample period is the whole log's median step even when
// the head's differs; errors name file:line:column as read_motion_samples'
// do. Logs come from the library (excitation.hpp, simulate.hpp) and are
// written with write_csv.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <numbers>
#include <random>

#include "identify/identify_file.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "summary_support.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

namespace fs = std::filesystem;

using test::kLevel;

using test::expect_close;
using test::expect_identical;

// Values near zero against their std (inertias and first moments differ in size).
void expect_same_motion_summary(const IdentifySummary& d, const IdentifySummary& s, double rel) {
  test::expect_same_summary(d, s, rel, /*residual_max=*/true, /*values_to_std=*/true);
}

void expect_same_base(const BaseParameters& a, const BaseParameters& b) {
  EXPECT_EQ(a.column, b.column);
  EXPECT_EQ(a.total_mass, b.total_mass);
  EXPECT_EQ(a.fixed_gravity, b.fixed_gravity);
  EXPECT_EQ(a.sensor_moving, b.sensor_moving);
  EXPECT_EQ(a.offset, b.offset);
  EXPECT_EQ(a.sensor_gravity, b.sensor_gravity);
}

// ------------------------------------------------------------ the accumulator

// A random motion sample set: random q, qd, qdd, gravity directions and (if
// `moving`) sensor motion; wrenches of the URDF's inertials with noise.
Samples random_motion(const Model& model, int n, bool moving, bool offset, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int nj = model.num_joints();
  Samples s;
  s.source = "random";
  s.q.resize(n, nj);
  s.qd.resize(n, nj);
  s.qdd.resize(n, nj);
  s.gravity.resize(n, 3);
  if (moving) s.sensor_motion.resize(n, 9);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < nj; ++j) {
      s.q(i, j) = model.joints[j].generic_position(u(rng));
      s.qd(i, j) = normal(rng);
      s.qdd(i, j) = 3.0 * normal(rng);
    }
    const Eigen::Vector3d g(normal(rng), normal(rng), normal(rng));
    s.gravity.row(i) = kStandardGravity * g.normalized().transpose();
    if (moving)
      for (int k = 0; k < 9; ++k) s.sensor_motion(i, k) = normal(rng);
    s.line.push_back(i + 1);
  }
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  so.seed = seed;
  if (offset) so.offset << 2.0, -1.0, 3.0, 0.2, -0.1, 0.05;
  s.wrench = simulate_wrenches(model, s, so);
  return s;
}

TEST(MotionAccumulator, AgreesWithIdentifyOnEveryExample) {
  for (const test::Example& ex : test::examples()) {
    const Model model = load_urdf(ex.urdf);
    for (const bool moving : {false, true})
      for (const bool offset : {false, true}) {
        SCOPED_TRACE(ex.name + (moving ? " moving" : " still") + (offset ? " offset" : ""));
        if (model.num_joints() == 0 && !moving) continue;  // a rigid tool needs motion
        BaseParameterOptions bo;
        bo.layout = ParameterLayout::full();
        bo.sensor_moving = moving;
        bo.offset = offset;
        const BaseParameters base = find_base_parameters(model, bo);
        const Samples s = random_motion(model, 3000, moving, offset, 7);
        const IdentifySummary dense = identify(model, base, s);
        StreamOptions so;
        so.block_rows = 700;
        const IdentifySummary streamed = identify_streaming(model, base, s, {}, so);
        expect_same_motion_summary(dense, streamed, 1e-9);
        // The same rows one at a time through add(MotionRow).
        IdentifyAccumulator acc(model, base);
        acc.set_source(s.source, false);
        acc.add(s);
        IdentifySummary added = acc.finish();
        added.residual_max = dense.residual_max;  // (not tracked here)
        expect_same_motion_summary(dense, added, 1e-9);
      }
  }
}

TEST(MotionAccumulator, UndeterminedMotionGivesTheDenseMessage) {
  // wrist_3 never moves: identify() names it; so must finish().
  const Model model = load_urdf(test::kUrLikeUrdf);
  FourierTrajectory tr = random_fourier_trajectory(model, 5, 10.0, 11);
  tr.a.row(5).setZero();
  tr.b.row(5).setZero();
  Samples s = sample_trajectory(tr, 10.0, 200.0, kLevel);
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
  s.wrench = simulate_wrenches(model, s, so);
  const BaseParameters base = find_base_parameters(model, motion_base_options(s, false));
  std::string dense, streamed;
  try {
    identify(model, base, s);
  } catch (const IdentifiabilityError& e) {
    dense = e.what();
  }
  try {
    identify_streaming(model, base, s);
  } catch (const IdentifiabilityError& e) {
    streamed = e.what();
  }
  EXPECT_NE(dense.find("wrist_3_joint"), std::string::npos) << dense;
  EXPECT_EQ(dense, streamed);
}

// ------------------------------------------------------------ motion logs

// A log's make-up: which columns the file has.
struct MotionLog {
  std::string sensor;               // sensor link ("" for the root)
  bool velocities = true;           // JOINT_vel, JOINT_acc of the measured joints
  bool upstream_velocities = true;  // ... of the joints above the sensor link
  bool gravity_columns = true;      // gx,gy,gz (else from the upstream joints or the force)
  bool sensor_columns = false;      // wx..az (a moving platform)
  bool offset = true;               // a sensor offset in the data
  int blocks = 0;                   // a block column with this many runs (0: none)
  double rate = 200.0, duration = 30.0;
  double tilt_after = -1.0;    // s: gravity tilts then, and again at twice that (< 0: never)
  double encoder_noise = 0.0;  // rad, on the positions
  std::uint64_t seed = 1;
};

class MotionCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("massid_motion_streaming_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Writes the log and returns its path; `edit` may change the rows first.
  std::string write(const std::string& name, const MotionLog& log,
                    const std::function<void(std::vector<std::string>&,
                                             std::vector<std::vector<std::string>>&)>& edit = {}) {
    const Model arm = load_urdf(test::kUrLikeUrdf);
    const Model model = load_urdf(test::kUrLikeUrdf, log.sensor);
    // One trajectory for every joint of the arm; the sensor's model takes its
    // joints (below) and upstream joints (above) from it by name.
    const FourierTrajectory tr = random_fourier_trajectory(arm, 5, 10.0, log.seed);
    const Samples all = sample_trajectory(tr, log.duration, log.rate, kLevel);
    const int n = all.size();
    const auto pick = [&](const std::vector<Joint>& joints, const Eigen::MatrixXd& from) {
      Eigen::MatrixXd m(n, static_cast<Eigen::Index>(joints.size()));
      for (size_t j = 0; j < joints.size(); ++j)
        m.col(static_cast<Eigen::Index>(j)) = from.col(arm.find_joint(joints[j].name));
      return m;
    };
    Samples s;
    s.source = name;
    s.q = pick(model.joints, all.q);
    s.qd = pick(model.joints, all.qd);
    s.qdd = pick(model.joints, all.qdd);
    s.q_upstream = pick(model.upstream_joints, all.q);
    s.qd_upstream = pick(model.upstream_joints, all.qd);
    s.qdd_upstream = pick(model.upstream_joints, all.qdd);
    s.time = all.time;
    s.line = all.line;
    s.gravity.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      // Level, then tilted about x, then (after twice the time) about y.
      const double t = s.time[i];
      Eigen::Vector3d g = kLevel;
      if (log.tilt_after >= 0 && t >= log.tilt_after)
        g = Eigen::AngleAxisd(0.3, t >= 2 * log.tilt_after ? Eigen::Vector3d::UnitY()
                                                           : Eigen::Vector3d::UnitX()) *
            kLevel;
      s.gravity.row(i) = g.transpose();
    }
    if (model.num_upstream_joints() > 0) {
      s.gravity_from_upstream = true;  // the arm's gravity in the sensor frame
      resolve_upstream(model, s);
    }
    if (log.sensor_columns) {
      s.sensor_motion.resize(n, 9);
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < 9; ++k) {
          const double t = s.time[i], f = 0.3 + 0.1 * k;
          // Still for the first 5 s, then a smooth sway (starting at rest).
          s.sensor_motion(i, k) = t < 5.0 ? 0.0 : 0.5 * (1.0 - std::cos(f * (t - 5.0)));
        }
    }
    SimulateOptions so;
    so.dynamic = true;
    so.noise_force = 0.1;
    so.noise_moment = 0.01;
    so.seed = log.seed;
    if (log.offset) so.offset << 2.0, -1.0, 3.0, 0.2, -0.1, 0.05;
    const Eigen::MatrixXd W = simulate_wrenches(model, s, so);

    std::mt19937_64 rng(log.seed + 100);
    std::normal_distribution<double> encoder(0.0, std::max(log.encoder_noise, 1e-300));
    const auto noisy = [&](double x) { return log.encoder_noise > 0 ? x + encoder(rng) : x; };
    std::vector<std::string> header{"t"};
    if (log.blocks > 0) header.push_back("block");
    for (const Joint& j : model.upstream_joints) header.push_back(j.name);
    if (log.upstream_velocities) {
      for (const Joint& j : model.upstream_joints) header.push_back(j.name + "_vel");
      for (const Joint& j : model.upstream_joints) header.push_back(j.name + "_acc");
    }
    for (const Joint& j : model.joints) header.push_back(j.name);
    if (log.velocities) {
      for (const Joint& j : model.joints) header.push_back(j.name + "_vel");
      for (const Joint& j : model.joints) header.push_back(j.name + "_acc");
    }
    if (log.gravity_columns)
      for (const char* c : {"gx", "gy", "gz"}) header.push_back(c);
    if (log.sensor_columns)
      for (const char* c : {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"})
        header.push_back(c);
    for (const char* c : kWrenchColumns) header.push_back(c);
    std::vector<std::vector<std::string>> rows(n);
    for (int i = 0; i < n; ++i) {
      auto& r = rows[i];
      r.push_back(format_number(s.time[i]));
      if (log.blocks > 0) r.push_back(std::to_string(7 + log.blocks * i / n));
      for (int j = 0; j < s.q_upstream.cols(); ++j)
        r.push_back(format_number(noisy(s.q_upstream(i, j))));
      if (log.upstream_velocities) {
        for (int j = 0; j < s.qd_upstream.cols(); ++j)
          r.push_back(format_number(s.qd_upstream(i, j)));
        for (int j = 0; j < s.qdd_upstream.cols(); ++j)
          r.push_back(format_number(s.qdd_upstream(i, j)));
      }
      for (int j = 0; j < s.q.cols(); ++j) r.push_back(format_number(noisy(s.q(i, j))));
      if (log.velocities) {
        for (int j = 0; j < s.qd.cols(); ++j) r.push_back(format_number(s.qd(i, j)));
        for (int j = 0; j < s.qdd.cols(); ++j) r.push_back(format_number(s.qdd(i, j)));
      }
      if (log.gravity_columns)
        for (int k = 0; k < 3; ++k) r.push_back(format_number(s.gravity(i, k)));
      if (log.sensor_columns)
        for (int k = 0; k < 9; ++k) r.push_back(format_number(s.sensor_motion(i, k)));
      for (int k = 0; k < 6; ++k) r.push_back(format_number(W(i, k)));
    }
    if (edit) edit(header, rows);
    const std::string p = path(name);
    write_csv(p, header, rows);
    return p;
  }

  // The in-memory path and the stream, compared; returns the stream's result.
  // (`model`: the log's model when it is not the URDF's at log.sensor.)
  MotionIdentification compare(const std::string& file, const MotionLog& log,
                               const StreamOptions& so, const MotionDataOptions& data = {},
                               const Model* other = nullptr) {
    const Model model = other ? *other : load_urdf(test::kUrLikeUrdf, log.sensor);
    MotionDataReport report;
    const Samples s = in_memory(model, file, data, report);
    const BaseParameters base = find_base_parameters(model, motion_base_options(s, log.offset));
    const IdentifySummary dense = identify(model, base, s);
    const MotionIdentification m = identify_motion_csv(model, file, log.offset, {}, data, so);
    expect_same_base(base, m.base);
    expect_same_motion_summary(dense, m.summary, 1e-9);
    EXPECT_EQ(report.rows, m.report.rows);
    EXPECT_EQ(report.derived, m.report.derived);
    EXPECT_EQ(report.decimation, m.report.decimation);
    EXPECT_EQ(report.kernels.half_width, m.report.kernels.half_width);
    EXPECT_EQ(report.kernels.smooth, m.report.kernels.smooth);
    // The head: the first prepared samples, bit for bit.
    const int h = m.head.size();
    EXPECT_GT(h, 0);
    if (h > 0 && h <= s.size()) {
      // An array a log does not have (sensor motion at rest, ...) is empty in
      // both (the head keeps its rows with no columns).
      const auto expect_head = [h](const Eigen::MatrixXd& head, const Eigen::MatrixXd& all,
                                   const char* name) {
        SCOPED_TRACE(name);
        if (all.size() == 0)
          EXPECT_EQ(head.cols(), 0);
        else
          EXPECT_EQ(head, all.topRows(h));
      };
      expect_head(m.head.q, s.q, "q");
      expect_head(m.head.qd, s.qd, "qd");
      expect_head(m.head.gravity, s.gravity, "gravity");
      expect_head(m.head.wrench, s.wrench, "wrench");
      expect_head(m.head.sensor_motion, s.sensor_motion, "sensor_motion");
      EXPECT_EQ(m.head.line, std::vector<int>(s.line.begin(), s.line.begin() + h));
    }
    return m;
  }

  // read_motion_samples. (For a model without measured joints, filter_motion
  // returns q with no rows, so that Samples::size() is 0: prepare_motion_samples
  // is repeated here with q sized to the filtered samples.)
  static Samples in_memory(const Model& model, const std::string& file,
                           const MotionDataOptions& data, MotionDataReport& report) {
    if (model.num_joints() > 0)
      return read_motion_samples(model, file, WrenchColumns::Required, data, &report);
    Samples raw = read_samples(model, read_csv(file), WrenchColumns::Required, data.samples);
    if (raw.qd_upstream.cols() > 0 || raw.has_sensor_motion())
      return prepare_motion_samples(model, std::move(raw), data, &report);
    report.rows = raw.size();
    report.derived = true;
    Samples s = filter_motion(raw, data.filter, &report.kernels);
    report.decimation = data.filter.decimation > 0
                            ? data.filter.decimation
                            : default_decimation(1.0 / report.kernels.dt, report.kernels.cutoff);
    s.q.resize(s.time.size(), 0);
    resolve_upstream(model, s);
    return s;
  }

  fs::path dir_;
};

// Small blocks and head: many blocks, most shorter than the filter window.
StreamOptions small_blocks(size_t bytes = 37000, int threads = 2) {
  StreamOptions so;
  so.block_bytes = bytes;
  so.pilot_bytes = 60000;
  so.threads = threads;
  return so;
}

TEST_F(MotionCsvTest, VelocitiesGivenAgreeWithInMemory) {
  for (const bool offset : {false, true}) {
    SCOPED_TRACE(offset ? "offset" : "no offset");
    MotionLog log;
    log.offset = offset;
    const std::string f = write("given.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_FALSE(m.report.derived);
    EXPECT_EQ(m.passes, 1);
    EXPECT_TRUE(m.base.fixed_gravity);
    // The default blocks and head (the file is smaller than the head).
    compare(f, log, StreamOptions{});
  }
}

TEST_F(MotionCsvTest, LargestResidualWithoutASecondPass) {
  // The three ways to the largest residual give the in-memory value (compare
  // checks it): the samples kept (the default for a log this size);
  // candidate rows proven against a pilot from the head and windows across
  // the file (nothing kept; a 6000-row log has little room between its
  // 1025th and its largest residual, so the pilot here is a third of it --
  // on 10^6 rows the default 2 MB head and windows prove it, see
  // docs/performance.md); and a second pass (a filtered log's pilot is its
  // head alone, too small to prove it).
  MotionLog log;
  const std::string f = write("residual.csv", log);
  StreamOptions so = small_blocks();
  EXPECT_FALSE(compare(f, log, so).residual_pass);
  so.keep_bytes = 0;
  so.pilot_bytes = 1 << 20;
  EXPECT_FALSE(compare(f, log, so).residual_pass);
  MotionLog filtered;
  filtered.velocities = false;
  const std::string g = write("residual_filtered.csv", filtered);
  so.pilot_bytes = 60000;
  EXPECT_TRUE(compare(g, filtered, so).residual_pass);
}

TEST_F(MotionCsvTest, VelocitiesDerivedInTheStreamAgreeWithInMemory) {
  for (const bool offset : {false, true}) {
    SCOPED_TRACE(offset ? "offset" : "no offset");
    MotionLog log;
    log.velocities = false;
    log.offset = offset;
    log.encoder_noise = 1e-5;
    const std::string f = write("derived.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_TRUE(m.report.derived);
    EXPECT_EQ(m.report.decimation, 10);
    EXPECT_EQ(m.passes, 1);
    // Every decimation phase and block size, and no decimation.
    for (const int D : {1, 3, 7}) {
      SCOPED_TRACE(D);
      MotionDataOptions data;
      data.filter.decimation = D;
      data.filter.cutoff = 8.0;
      compare(f, log, small_blocks(4000 + 997 * D), data);
    }
  }
}

TEST_F(MotionCsvTest, BlockColumnRestartsTheFilter) {
  MotionLog log;
  log.velocities = false;
  log.blocks = 3;
  const std::string f = write("blocks.csv", log);
  compare(f, log, small_blocks());
  compare(f, log, small_blocks(2500));
}

TEST_F(MotionCsvTest, WristSensorWithTheArmJointsAbove) {
  // A tool on wrist_3_link: no measured joints; gravity and the sensor's
  // motion from the six arm joints (given velocities, then derived).
  for (const bool given : {true, false}) {
    SCOPED_TRACE(given ? "given" : "derived");
    MotionLog log;
    log.sensor = "wrist_3_link";
    log.gravity_columns = false;
    log.upstream_velocities = given;
    log.offset = false;
    const std::string f = write("wrist.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_TRUE(m.base.sensor_moving);
    EXPECT_EQ(m.report.derived, !given);
  }
}

// A tool on wrist_3_link, gravity and the sensor's motion from the arm's
// joints (velocities derived), no offset.
MotionLog wrist_log_derived() {
  MotionLog log;
  log.sensor = "wrist_3_link";
  log.gravity_columns = false;
  log.upstream_velocities = false;
  log.offset = false;
  return log;
}

TEST_F(MotionCsvTest, WristSensorPoseInMemoryAsInTheStream) {
  // The wrist log with the arm's joints replaced by the sensor's pose in the
  // world (qx,qy,qz,qw from the arm's own kinematics, every fifth row's sign
  // negated, and x,y,z), velocities derived, then given (the quaternion's
  // rates from the sensor frame's body rates of upstream_kinematics: qd = q
  // (x) (0, w) / 2, qdd = (qd (x) (0, w) + q (x) (0, dw)) / 2, negated with
  // it; xdd = R a, xd = 0: nothing reads it): the stream (its blocks and
  // margins) gives the in-memory fit, the sensor moves, and the fit is the
  // joints' (to a small fraction of its std when the filter derives: it
  // smooths other signals; to rounding when the rates are given).
  const Model arm = load_urdf(test::kUrLikeUrdf);
  const int wrist = arm.find_link("wrist_3_link");
  for (const bool given : {false, true}) {
    SCOPED_TRACE(given ? "given" : "derived");
    MotionLog log = wrist_log_derived();
    log.upstream_velocities = given;
    const Model model = load_urdf(test::kUrLikeUrdf, log.sensor);
    const std::string f = write("pose.csv", log, [&](auto& header, auto& rows) {
      const auto column = [&](const std::string& name) {
        return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
      };
      const size_t first_other = given ? 19 : 7;  // after t and the joints' columns
      KinematicsData kin(arm);
      const auto quat = [](const Eigen::Vector3d& v) {
        return Eigen::Quaterniond(0, v.x(), v.y(), v.z());
      };
      for (size_t i = 0; i < rows.size(); ++i) {
        Eigen::VectorXd q(arm.num_joints()), qd = Eigen::VectorXd::Zero(arm.num_joints()), qdd = qd;
        for (int j = 0; j < arm.num_joints(); ++j) {
          const std::string& name = arm.joints[static_cast<size_t>(j)].name;
          q[j] = std::stod(rows[i][column(name)]);
          if (given) {
            qd[j] = std::stod(rows[i][column(name + "_vel")]);
            qdd[j] = std::stod(rows[i][column(name + "_acc")]);
          }
        }
        forward_kinematics(arm, kin, q);
        const Eigen::Matrix3d R = kin.rotation[wrist];
        Eigen::Quaterniond h(R);
        if (i % 5 == 0) h.coeffs() = -h.coeffs();
        std::vector<double> v = {h.x(), h.y(), h.z(), h.w()};
        for (int k = 0; k < 3; ++k) v.push_back(kin.position[wrist][k]);
        if (given) {  // the arm's joints are the wrist model's upstream joints, in order
          const SensorPose p = upstream_kinematics(model, q, qd, qdd);
          const Eigen::Quaterniond hd = h * quat(0.5 * p.motion.omega);
          Eigen::Quaterniond hdd = hd * quat(0.5 * p.motion.omega);
          hdd.coeffs() += (h * quat(0.5 * p.motion.omega_dot)).coeffs();
          const Eigen::Vector3d xdd = R * p.motion.accel;
          v.insert(v.end(), {hd.x(), hd.y(), hd.z(), hd.w(), 0, 0, 0});
          v.insert(v.end(), {hdd.x(), hdd.y(), hdd.z(), hdd.w(), xdd.x(), xdd.y(), xdd.z()});
        }
        std::vector<std::string> row = {rows[i][0]};
        for (const double x : v) row.push_back(format_number(x));
        row.insert(row.end(), rows[i].begin() + static_cast<std::ptrdiff_t>(first_other),
                   rows[i].end());
        rows[i] = row;
      }
      std::vector<std::string> h = {"t"};
      for (const char* suffix : {"", "_vel", "_acc"}) {
        if (*suffix && !given) break;
        for (const char* n : {"qx", "qy", "qz", "qw", "x", "y", "z"})
          h.push_back(std::string(n) + suffix);
      }
      h.insert(h.end(), header.begin() + static_cast<std::ptrdiff_t>(first_other), header.end());
      header = h;
    });
    const Model pose = with_sensor_pose(model, SensorPoseColumns::Quaternion, true);
    const MotionIdentification m = compare(f, log, small_blocks(), {}, &pose);
    EXPECT_TRUE(m.base.sensor_moving);
    EXPECT_EQ(m.report.derived, !given);
    const std::string g = write("joints.csv", log);
    const MotionIdentification j = compare(g, log, small_blocks());
    ASSERT_EQ(j.summary.value.size(), m.summary.value.size());
    for (Eigen::Index k = 0; k < j.summary.value.size(); ++k)
      EXPECT_NEAR(m.summary.value[k], j.summary.value[k],
                  given ? 1e-9 * (1 + std::abs(j.summary.value[k])) : 0.3 * j.summary.stddev[k])
          << k;
  }
}

TEST_F(MotionCsvTest, RootGravityHoldsAfterTheFilterInMemoryAsInTheStream) {
  // Gravity from the arm joints above a wrist sensor, in a root frame whose
  // gravity is not the default, velocities derived: after the filter the
  // in-memory samples' gravity is the given root gravity turned into the
  // sensor frame at the filtered upstream positions (it once fell back to
  // the default root gravity there, which the stream never did).
  const MotionLog log = wrist_log_derived();
  const std::string f = write("root_gravity.csv", log);
  MotionDataOptions data;
  data.samples.root_gravity = Eigen::Vector3d(1.2, -0.7, -9.7);
  const MotionIdentification m = compare(f, log, small_blocks(), data);
  EXPECT_TRUE(m.report.derived);
  const Model model = load_urdf(test::kUrLikeUrdf, log.sensor);
  MotionDataReport report;
  const Samples s = in_memory(model, f, data, report);
  ASSERT_GT(s.size(), 0);
  for (const int i : {0, s.size() / 2, s.size() - 1}) {
    const Eigen::VectorXd qu = s.q_upstream.row(i).transpose();
    Eigen::Vector3d g;
    upstream_sensor_frame(model, qu.data(), nullptr, nullptr, data.samples.root_gravity, g.data(),
                          nullptr);
    EXPECT_EQ(s.gravity.row(i).transpose(), g) << "sample " << i;
    EXPECT_NEAR(s.gravity.row(i).norm(), data.samples.root_gravity.norm(), 1e-12);
  }
}

TEST_F(MotionCsvTest, SensorMidChainWithMixedColumns) {
  // Sensor on wrist_1_link: two joints below, four above. Below given and
  // above derived, and the other way round (the sensor's motion then comes
  // from the raw upstream velocities and is smoothed like the wrench).
  for (const bool below_given : {true, false}) {
    SCOPED_TRACE(below_given ? "below given" : "above given");
    MotionLog log;
    log.sensor = "wrist_1_link";
    log.velocities = below_given;
    log.upstream_velocities = !below_given;
    log.gravity_columns = below_given;  // from the upstream joints in the other case
    const std::string f = write("mid.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_TRUE(m.report.derived);
    EXPECT_TRUE(m.base.sensor_moving);
  }
}

TEST_F(MotionCsvTest, ThreadCountDoesNotChangeTheResult) {
  for (const bool given : {true, false}) {
    SCOPED_TRACE(given ? "given" : "derived");
    MotionLog log;
    log.velocities = given;
    const std::string f = write("threads.csv", log);
    const Model model = load_urdf(test::kUrLikeUrdf);
    const MotionIdentification one =
        identify_motion_csv(model, f, true, {}, {}, small_blocks(20000, 1));
    for (const int threads : {2, 4}) {
      const MotionIdentification other =
          identify_motion_csv(model, f, true, {}, {}, small_blocks(20000, threads));
      expect_identical(one.summary, other.summary);
    }
  }
}

TEST_F(MotionCsvTest, WhatTheHeadSuggestsIsCheckedAgainstTheWholeFile) {
  // Gravity level in the head, tilted later: the base is the one for varying
  // gravity (the total mass is then identifiable with offsets).
  {
    MotionLog log;
    log.velocities = false;
    log.tilt_after = 10.0;
    const std::string f = write("tilt.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_FALSE(m.base.fixed_gravity);
    EXPECT_GE(m.base.total_mass, 0);
    EXPECT_EQ(m.passes, 2);
  }
  // A platform at rest in the head, swaying later.
  {
    MotionLog log;
    log.sensor_columns = true;
    const std::string f = write("sway.csv", log);
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_TRUE(m.base.sensor_moving);
    EXPECT_EQ(m.passes, 2);
  }
  // A sample period that differs between the head and the rest (within the
  // 0.1 % uniformity): the median of all steps, as filter_motion takes it.
  {
    MotionLog log;
    log.velocities = false;
    const std::string f = write("period.csv", log, [](auto& header, auto& rows) {
      const size_t n = rows.size();
      double t = 0.0;
      for (size_t i = 0; i < n; ++i) {
        rows[i][0] = format_number(t);
        t += (i < n / 3 ? 1.0004 : 0.9997) * 0.005;  // the head is in the first third
      }
      (void)header;
    });
    const MotionIdentification m = compare(f, log, small_blocks());
    EXPECT_EQ(m.passes, 1);  // the period comes from a scan of t before the stream
  }
}

// ------------------------------------------------------------ errors

std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(MotionCsvTest, ErrorsAreThoseOfReadMotionSamples) {
  MotionLog log;
  log.velocities = false;
  log.blocks = 2;
  log.sensor_columns = true;
  const Model model = load_urdf(test::kUrLikeUrdf);
  // A bad cell deep in the file (line 4001: far beyond the head) in each kind of new column.
  const auto with_cell = [&](const std::string& column, const std::string& value) {
    return [=](std::vector<std::string>& header, std::vector<std::vector<std::string>>& rows) {
      const auto it = std::find(header.begin(), header.end(), column);
      ASSERT_NE(it, header.end()) << column;
      rows[3999][static_cast<size_t>(it - header.begin())] = value;
    };
  };
  const std::vector<std::pair<
      std::string,
      std::function<void(std::vector<std::string>&, std::vector<std::vector<std::string>>&)>>>
      cases = {
          {"t", with_cell("t", "soon")},
          {"wx", with_cell("wx", "")},
          {"az", with_cell("az", "1e999")},
          {"block", with_cell("block", "7.5")},
          {"joint", with_cell("elbow_joint", "nan")},
          {"repeat", with_cell("t", "19.99")},  // t of the previous row: repeats
          {"back", with_cell("t", "19.9")},     // before the previous row
          {"gap", with_cell("t", "20.2")},      // a gap (then the next step goes back)
          {"short_row", [](auto&, auto& rows) { rows[3999].pop_back(); }},
      };
  for (const auto& [name, edit] : cases) {
    SCOPED_TRACE(name);
    const std::string f = write(name + ".csv", log, edit);
    MotionDataOptions data;
    const std::string dense =
        input_error([&] { read_motion_samples(model, f, WrenchColumns::Required, data); });
    ASSERT_NE(dense, "");
    EXPECT_NE(dense.find(f + ":"), std::string::npos) << dense;
    for (const int threads : {1, 2}) {
      EXPECT_EQ(input_error([&] {
                  identify_motion_csv(model, f, false, {}, data, small_blocks(30000, threads));
                }),
                dense);
    }
  }
  // Header rules: the same messages.
  const std::vector<std::pair<std::string, std::string>> headers = {
      {"vel_without_acc", "_acc"},
      {"some_vel", "_vel"},
      {"some_sensor", "wx"},
  };
  for (const auto& header_case : headers) {
    const std::string& name = header_case.first;   // (lambdas below capture them:
    const std::string& drop = header_case.second;  // no structured binding, for clang 14)
    SCOPED_TRACE(name);
    MotionLog given;
    given.sensor_columns = true;
    const std::string f = write(name + ".csv", given, [&](auto& header, auto& rows) {
      // Drop every column ending in `drop` (or only the first one for "some_").
      const bool one = name.rfind("some_", 0) == 0;
      for (size_t c = header.size(); c-- > 0;) {
        const std::string& h = header[c];
        if (h.size() >= drop.size() && h.compare(h.size() - drop.size(), drop.size(), drop) == 0) {
          header.erase(header.begin() + static_cast<std::ptrdiff_t>(c));
          for (auto& r : rows) r.erase(r.begin() + static_cast<std::ptrdiff_t>(c));
          if (one) break;
        }
      }
    });
    const std::string dense =
        input_error([&] { read_motion_samples(model, f, WrenchColumns::Required, {}); });
    ASSERT_NE(dense, "");
    EXPECT_EQ(input_error([&] { identify_motion_csv(model, f, false, {}, {}, small_blocks()); }),
              dense);
  }
  // No velocities and no t.
  {
    MotionLog no_t;
    no_t.velocities = false;
    const std::string f = write("no_t.csv", no_t, [](auto& header, auto& rows) {
      header.erase(header.begin());
      for (auto& r : rows) r.erase(r.begin());
    });
    const std::string dense =
        input_error([&] { read_motion_samples(model, f, WrenchColumns::Required, {}); });
    ASSERT_NE(dense, "");
    EXPECT_EQ(input_error([&] { identify_motion_csv(model, f, false, {}, {}, small_blocks()); }),
              dense);
  }
}

// ------------------------------------------------------------ identify_motion_file

TEST_F(MotionCsvTest, IdentifyMotionFileIsTheInMemoryPath) {
  MotionLog log;
  log.velocities = false;
  const std::string f = write("file.csv", log);
  const Model model = load_urdf(test::kUrLikeUrdf);
  MotionDataReport report;
  const Samples s = read_motion_samples(model, f, WrenchColumns::Required, {}, &report);
  const BaseParameters base = find_base_parameters(model, motion_base_options(s, true));
  const IdentifySummary dense = identify(model, base, s);
  BaseParameters streamed_base;
  MotionDataReport streamed_report;
  Samples head;
  const IdentifySummary streamed =
      identify_motion_file(model, f, true, {}, {}, &streamed_base, &streamed_report, &head);
  expect_same_base(base, streamed_base);
  expect_same_motion_summary(dense, streamed, 1e-9);
  EXPECT_EQ(streamed_report.rows, report.rows);
  EXPECT_GT(head.size(), 0);
  // --robust: in memory, the same as identify() with it.
  IdentifyOptions robust;
  robust.robust = true;
  const IdentifySummary r = identify_motion_file(model, f, true, robust, {}, &streamed_base);
  expect_same_motion_summary(identify(model, base, s, robust), r, 1e-12);
}

// ------------------------------------------------------------ static logs

TEST_F(MotionCsvTest, StaticWristLogTakesGravityFromTheArmJoints) {
  // A static log of a wrist sensor without gx,gy,gz: read_samples takes
  // gravity from the arm's joints; so does the static stream.
  const Model model = load_urdf(test::kUrLikeUrdf, "wrist_3_link");
  MotionLog log;
  log.sensor = "wrist_3_link";
  log.gravity_columns = false;
  log.upstream_velocities = false;
  const std::string f = write("static_wrist.csv", log);
  const Samples s = read_samples(model, read_csv(f), WrenchColumns::Required);
  ASSERT_TRUE(s.gravity_from_upstream);
  const BaseParameters base = find_base_parameters(model);
  StreamOptions so;
  so.block_bytes = 50000;
  expect_same_motion_summary(identify(model, base, s), identify_csv(model, base, f, {}, so), 1e-9);
}

TEST_F(MotionCsvTest, StaticWristLogWithRootGravityEveryReaderAgreesWithTheUrdf) {
  // A tool on a wrist sensor at rest, the arm on a tilted wall: a log without
  // gx,gy,gz. Every reader (in memory, streamed, identify_file and
  // identify(model, request, source) as the CLI and Python run them, the arrays of Python) takes
  // gravity from the arm's joints and the root gravity given, and the fit
  // finds the URDF's tool.
  const Model arm = load_urdf(test::kUrLikeUrdf);
  const Model model = load_urdf(test::kUrLikeUrdf, "wrist_3_link");
  const int nu = model.num_upstream_joints();
  ASSERT_EQ(nu, arm.num_joints());
  SampleOptions read;
  read.root_gravity =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * Eigen::Vector3d(-kStandardGravity, 0, 0);
  // Random poses; gravity in the wrist frame from the whole arm's kinematics
  // (forward_kinematics, not the upstream_kinematics the readers use).
  const int n = 300;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  Samples plan;
  plan.q.resize(n, 0);
  plan.q_upstream.resize(n, nu);
  plan.gravity.resize(n, 3);
  KinematicsData kin(arm);
  const int wrist = arm.find_link("wrist_3_link");
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd q(arm.num_joints());
    for (int j = 0; j < arm.num_joints(); ++j) q[j] = angle(rng);
    forward_kinematics(arm, kin, q);
    for (int j = 0; j < nu; ++j)
      plan.q_upstream(i, j) = q[arm.find_joint(model.upstream_joints[j].name)];
    plan.gravity.row(i) = (kin.rotation[wrist].transpose() * read.root_gravity).transpose();
  }
  SimulateOptions sim;
  sim.noise_force = 0.05;
  sim.noise_moment = 0.005;
  const Eigen::MatrixXd W = simulate_wrenches(model, plan, sim);
  // The first joint in degrees (a scaled column).
  std::vector<std::string> header;
  for (int j = 0; j < nu; ++j)
    header.push_back(model.upstream_joints[j].name + (j == 0 ? "_deg" : ""));
  for (const char* c : kWrenchColumns) header.push_back(c);
  std::vector<std::vector<std::string>> rows(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < nu; ++j)
      rows[i].push_back(format_number(j == 0 ? plan.q_upstream(i, j) * 180.0 / std::numbers::pi
                                             : plan.q_upstream(i, j)));
    for (int k = 0; k < 6; ++k) rows[i].push_back(format_number(W(i, k)));
  }
  const std::string f = path("static_wrist_wall.csv");
  write_csv(f, header, rows);

  const BaseParameters base = find_base_parameters(model);
  const Samples s = read_samples(model, read_csv(f), WrenchColumns::Required, read);
  ASSERT_TRUE(s.gravity_from_upstream);
  EXPECT_LT((s.gravity - plan.gravity).cwiseAbs().maxCoeff(), 1e-9);
  const IdentifySummary dense = identify(model, base, s);
  const Eigen::VectorXd truth = base.K * nominal_standard_parameters(model);
  for (int k = 0; k < truth.size(); ++k)
    EXPECT_LT(std::abs(dense.value[k] - truth[k]), 5 * dense.stddev[k] + 1e-9) << k;

  // Streamed from the file, in blocks.
  StreamOptions so;
  so.block_bytes = 5000;
  IdentifySummary streamed = accumulate_csv(model, base, f, so, read).finish();
  streamed.residual_max = residual_max_csv(model, base, f, streamed.value, so, read);
  expect_same_motion_summary(dense, streamed, 1e-9);
  // As massid identify and massid.identify(path) run it.
  expect_same_motion_summary(dense, identify_file(model, base, f, {}, nullptr, read), 1e-9);
  IdentifyRequest request;
  request.root_gravity = read.root_gravity;
  expect_same_motion_summary(dense, identify(model, request, IdentifySource::file(f)).summary,
                             1e-9);
  // The set-up checks read the same gravity: no error.
  SetupCheckOptions checks;
  checks.read = read;
  EXPECT_FALSE(has_error(check_setup_file(model, f, checks)));
  // Python's arrays (the same map).
  const CsvTable table = read_csv(f);
  std::vector<Eigen::VectorXd> columns(table.num_columns(), Eigen::VectorXd(table.num_rows()));
  for (int c = 0; c < table.num_columns(); ++c)
    for (int r = 0; r < table.num_rows(); ++r) columns[c][r] = table.number(r, c);
  const Samples arrays =
      samples_from_columns(model, table.header, columns, WrenchColumns::Required, "data", read);
  ASSERT_TRUE(arrays.gravity_from_upstream);
  EXPECT_EQ(arrays.gravity, s.gravity);
  // The root gravity matters: the default one is another gravity.
  EXPECT_GT((read_samples(model, table, WrenchColumns::Required).gravity - s.gravity).norm(), 10.0);
}

}  // namespace
}  // namespace massid

// `massid compensate --track` run as a user would: a params file identified
// in motion from a free log of the tool on the wrist sensor, then a tracked
// log (an object grasped and put down at rest, drifting offsets, a contact;
// tracker_support.hpp) through stdin. Checked: the spec's columns in order,
// the events, the payload's mass against the object's, *_comp against the
// contact wrench put into the data.
#include <Eigen/Geometry>
#include <chrono>
#include <regex>
#include <thread>

#include "cli_support.hpp"
#include "massid/core/kinematics.hpp"
#include "tracker_support.hpp"

namespace massid_cli_test {
namespace {

using namespace massid::tracker_test;

class CliTracker : public Cli {
 protected:
  // The tool's dynamic params, identified from a log without events.
  std::string params() {
    const std::string free_log =
        file("free.csv", tracker_csv(tracker_log(true, 11, false), massid::load_urdf(kUrUrdf)));
    const Result r = run({"identify", kUrUrdf, free_log, "--dynamic", "--sensor", "wrist_3_link",
                          "-o", path("tool.json")});
    EXPECT_EQ(r.code, 0) << r;
    return path("tool.json");
  }
};

TEST_F(CliTracker, TrackAppendsTheSpecsColumnsAndTracksTheObject) {
  const std::string tool = params();
  const TrackerLog log = tracker_log(true, 12);
  const std::string in = file("tracked.csv", tracker_csv(log, massid::load_urdf(kUrUrdf)));
  Result r = run({"compensate", kUrUrdf, tool, "--track", "--stats"}, in);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("tracking a payload on link 'tool'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tracker update"), std::string::npos) << r.err;
  write_file(path("out.csv"), r.out);
  const Table t = read_table(path("out.csv"));
  ASSERT_EQ(t.rows.size(), static_cast<std::size_t>(log.samples.size()));
  // The columns: the input's, fx_comp..mz_comp, then the spec's, in order.
  const std::vector<std::string> tracked = {
      "payload_m",     "payload_cx",  "payload_cy",  "payload_cz",  "payload_m_std",
      "payload_c_std", "payload_ixx", "payload_ixy", "payload_ixz", "payload_iyy",
      "payload_iyz",   "payload_izz", "offset_fx",   "offset_fy",   "offset_fz",
      "offset_mx",     "offset_my",   "offset_mz",   "event"};
  const int comp = t.col("fx_comp");
  ASSERT_GE(comp, 0);
  ASSERT_EQ(t.header.size(), static_cast<std::size_t>(comp + 6) + tracked.size());
  for (std::size_t k = 0; k < tracked.size(); ++k)
    EXPECT_EQ(t.header[static_cast<std::size_t>(comp + 6) + k], tracked[k]);
  const int event = t.col("event"), ixx = t.col("payload_ixx");
  int changes = 0, contact = 0, contact_rows = 0;
  double worst_mass = 0, worst_comp_f = 0, worst_comp_m = 0, sq_f = 0, sq_m = 0;
  int in_contact = 0;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const double time = t.num(i, "t");
    const std::string& e = t.rows[i][static_cast<std::size_t>(event)];
    changes += e == "change";
    if (tracker_in_contact(time)) {
      ++contact_rows;
      contact += e == "contact";
    }
    if (time >= kGrasp + 1.0 && time < kRelease)
      worst_mass = std::max(worst_mass, std::abs(t.num(i, "payload_m") - kObjectMass));
    // The inertia: undetermined at rest after the grasp, determined by the
    // end of the motion that follows.
    const std::string& inertia = t.rows[i][static_cast<std::size_t>(ixx)];
    if (time >= kGrasp + 0.5 && time < kGrasp + 1.5) {
      EXPECT_EQ(inertia, "") << time;
    }
    if (time >= kMotion[1].b - 1.0 && time < kMotion[1].b) {
      EXPECT_NE(inertia, "") << time;
    }
    // In contact, *_comp is the contact's wrench: its error is the noise's
    // (RMS within 1.5 sigma, every row within 5.5 sigma; the ramps excluded).
    if (time >= kContactStart + 0.1 && time < kContactEnd - 0.1) {
      const massid::Wrench c = tracker_contact_wrench(log, static_cast<int>(i));
      ++in_contact;
      for (int k = 0; k < 6; ++k) {
        const double d =
            std::abs(t.num(i, std::string(massid::kWrenchColumns[k]) + "_comp") - c[k]);
        (k < 3 ? worst_comp_f : worst_comp_m) = std::max(k < 3 ? worst_comp_f : worst_comp_m, d);
        (k < 3 ? sq_f : sq_m) += d * d / 3;
      }
    }
  }
  EXPECT_EQ(changes, 2);
  EXPECT_GE(contact, 0.9 * contact_rows);
  EXPECT_LT(worst_mass, 0.01 * kObjectMass);
  EXPECT_LT(std::sqrt(sq_f / in_contact), 1.5 * 0.05);
  EXPECT_LT(std::sqrt(sq_m / in_contact), 1.5 * 0.003);
  EXPECT_LT(worst_comp_f, 5.5 * 0.05);
  EXPECT_LT(worst_comp_m, 5.5 * 0.003);
}

// The same tracked lines over loopback UDP (one datagram each, --udp 0)
// give the same output, to the byte, as on stdin.
TEST_F(CliTracker, TrackOverUdpIsTrackOnStdin) {
  const std::string tool = params();
  const std::string csv = tracker_csv(tracker_log(true, 14), massid::load_urdf(kUrUrdf));
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (std::size_t next; (next = csv.find('\n', at)) != std::string::npos && lines.size() < 1500;
       at = next + 1)
    lines.push_back(csv.substr(at, next - at));
  std::string head;
  for (const std::string& l : lines) head += l + "\n";
  const Result stdin_run = run({"compensate", kUrUrdf, tool, "--track"}, file("head.csv", head));
  ASSERT_EQ(stdin_run.code, 0) << stdin_run;

  Result udp_run;
  std::thread command([&] {
    udp_run = run({"compensate", kUrUrdf, tool, "--track", "--udp", "0"});
  });
  // The port, from the command's stderr.
  int port = 0;
  for (int k = 0; k < 1000 && port == 0; ++k) {
    std::smatch m;
    const std::string err = read_file(path(".stderr"));
    if (std::regex_search(err, m, std::regex(R"(udp 127\.0\.0\.1:(\d+))")))
      port = std::stoi(m[1]);
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_GT(port, 0);
  const LoopbackSender sender(port);
  for (std::size_t i = 0; i <= lines.size(); ++i) {
    EXPECT_TRUE(sender.send(i < lines.size() ? lines[i] : ""));  // "" ends the stream
    if (i % 50 == 49) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  command.join();
  EXPECT_EQ(udp_run.code, 0) << udp_run.err;
  EXPECT_EQ(udp_run.out, stdin_run.out);
}

TEST_F(CliTracker, TrackNeedsTimeAndNamesAWrongPayloadLink) {
  const std::string tool = params();
  const std::string no_t = file("no_t.csv", "gx,gy,gz,fx,fy,fz,mx,my,mz\n0,0,-9.8,0,0,0,0,0,0\n");
  Result r = run({"compensate", kUrUrdf, tool, "--track"}, no_t);
  EXPECT_NE(r.code, 0) << r;
  EXPECT_NE(r.err.find("--track needs the time column t"), std::string::npos) << r;
  const std::string in =
      file("one.csv", tracker_csv(tracker_log(true, 13, false), massid::load_urdf(kUrUrdf)));
  r = run({"compensate", kUrUrdf, tool, "--track", "--payload-link", "gripper"}, in);
  EXPECT_NE(r.code, 0) << r;
  EXPECT_NE(r.err.find("'gripper'"), std::string::npos) << r;
  // A tracking column already in the input.
  const std::string with_event =
      file("event.csv", "t,event,gx,gy,gz,fx,fy,fz,mx,my,mz\n0,1,0,0,-9.8,0,0,0,0,0,0\n");
  r = run({"compensate", kUrUrdf, tool, "--track"}, with_event);
  EXPECT_NE(r.code, 0) << r;
  EXPECT_NE(r.err.find("'event'"), std::string::npos) << r;
  // t going back: the line is named and skipped.
  const std::string back =
      file("back.csv",
           "t,gx,gy,gz,fx,fy,fz,mx,my,mz\n0.1,0,0,-9.8,0,0,0,0,0,0\n0.05,0,0,-9.8,0,0,0,0,0,0\n"
           "0.2,0,0,-9.8,0,0,0,0,0,0\n");
  r = run({"compensate", kUrUrdf, tool, "--track"}, back);
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("stdin:3: t = 0.05 does not increase"), std::string::npos) << r;
  EXPECT_EQ(count_lines(r.out), 3) << r;  // the header and two samples
  r = run({"compensate", kUrUrdf, tool, "--payload-link", "tool"}, in);
  EXPECT_NE(r.code, 0) << r;
  EXPECT_NE(r.err.find("--track"), std::string::npos) << r;
}

// A tracked log with pose columns (quaternions) gives the same estimates as
// the same log given by joints (issue 28): the wrist sensor's orientation
// and origin in the world from the arm's own forward kinematics (the sensor
// at the arm's base), their rates from the joints' (the sensor frame's body
// rates omega, omega_dot and origin acceleration a from upstream_kinematics:
// qd = q (x) (0, omega) / 2, qdd = (qd (x) (0, omega) + q (x) (0, omega_dot)) / 2,
// xdd = R a; xd by central differences, which nothing reads; every seventh
// row's quaternion negated, its rates with it: compensate makes the sign
// continuous and must turn the rates with it). compensate
// does not derive rates from t (a live stream): the log gives them, as it
// gives the joints' _vel, _acc. Every tracked column agrees to rounding.
TEST_F(CliTracker, TrackedLogWithPoseColumnsGivesTheEstimatesOfTheJoints) {
  const std::string tool = params();
  const TrackerLog log = tracker_log(true, 12);
  const massid::Model arm = massid::load_urdf(kUrUrdf);
  const std::string by_joints = file("joints.csv", tracker_csv(log, arm));
  const int wrist = arm.find_link("wrist_3_link");
  massid::KinematicsData kin(arm);
  const auto origin = [&](const Eigen::VectorXd& q) {
    massid::forward_kinematics(arm, kin, q);
    return Eigen::Vector3d(kin.position[wrist]);
  };
  const auto quat = [](const Eigen::Vector3d& v) {
    return Eigen::Quaterniond(0, v.x(), v.y(), v.z());
  };
  const auto cells = [](const Eigen::Quaterniond& h) {
    return fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g}", h.x(), h.y(), h.z(), h.w());
  };
  const auto cells3 = [](const Eigen::Vector3d& v) {
    return fmt::format(",{:.17g},{:.17g},{:.17g}", v.x(), v.y(), v.z());
  };
  std::string csv =
      "t,qx,qy,qz,qw,x,y,z,qx_vel,qy_vel,qz_vel,qw_vel,x_vel,y_vel,z_vel,qx_acc,qy_acc,qz_acc,"
      "qw_acc,x_acc,y_acc,z_acc,fx,fy,fz,mx,my,mz\n";
  const massid::Samples& s = log.samples;
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::VectorXd q = s.q_upstream.row(i).transpose(),
                          qd = s.qd_upstream.row(i).transpose(),
                          qdd = s.qdd_upstream.row(i).transpose();
    const massid::SensorPose p = massid::upstream_kinematics(log.plain, q, qd, qdd);
    forward_kinematics(arm, kin, q);
    const Eigen::Matrix3d R = kin.rotation[wrist];
    const Eigen::Vector3d x = kin.position[wrist];
    Eigen::Quaterniond h(R);
    if (i % 7 == 0) h.coeffs() = -h.coeffs();  // the same rotation (its rates follow)
    const Eigen::Quaterniond hd = h * quat(0.5 * p.motion.omega);
    Eigen::Quaterniond hdd = hd * quat(0.5 * p.motion.omega);
    hdd.coeffs() += (h * quat(0.5 * p.motion.omega_dot)).coeffs();
    const double dt = 1e-6;
    const Eigen::Vector3d xd = (origin(q + dt * qd) - origin(q - dt * qd)) / (2 * dt);
    csv += fmt::format("{}", s.time[i]) + cells(h) + cells3(x) + cells(hd) + cells3(xd) +
           cells(hdd) + cells3(R * p.motion.accel);
    for (int k = 0; k < 6; ++k) csv += fmt::format(",{}", s.wrench(i, k));
    csv += "\n";
  }
  const std::string by_pose = file("pose.csv", csv);
  const Result a = run({"compensate", kUrUrdf, tool, "--track"}, by_joints);
  const Result b = run({"compensate", kUrUrdf, tool, "--track"}, by_pose);
  ASSERT_EQ(a.code, 0) << a;
  ASSERT_EQ(b.code, 0) << b;
  EXPECT_NE(b.err.find("the sensor's pose from qx,qy,qz,qw,x,y,z"), std::string::npos) << b.err;
  write_file(path("a.csv"), a.out);
  write_file(path("b.csv"), b.out);
  const Table ta = read_table(path("a.csv")), tb = read_table(path("b.csv"));
  ASSERT_EQ(ta.rows.size(), static_cast<std::size_t>(s.size()));
  ASSERT_EQ(tb.rows.size(), ta.rows.size());
  const int event = ta.col("event");
  int changes = 0;
  double worst = 0;
  for (std::size_t i = 0; i < ta.rows.size(); ++i) {
    const std::string& e = ta.rows[i][static_cast<std::size_t>(event)];
    EXPECT_EQ(tb.rows[i][static_cast<std::size_t>(tb.col("event"))], e) << i;
    changes += e == "change";
    for (int c = ta.col("fx_comp"); c < event; ++c) {
      const std::string& name = ta.header[static_cast<std::size_t>(c)];
      const std::string& u = ta.rows[i][static_cast<std::size_t>(c)];
      const std::string& v = tb.rows[i][static_cast<std::size_t>(tb.col(name))];
      ASSERT_EQ(u.empty(), v.empty()) << name << " row " << i;
      // to rounding: relative beyond 1 (payload_c_std reaches 1e3 m while the
      // mass is near 0, at a change)
      if (!u.empty())
        worst = std::max(
            worst, std::abs(std::stod(u) - std::stod(v)) / std::max(1.0, std::abs(std::stod(u))));
    }
  }
  EXPECT_EQ(changes, 2);  // the grasp and the release: the log's events
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace massid_cli_test

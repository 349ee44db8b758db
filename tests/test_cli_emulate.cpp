// `massid emulate`: trace and summary files, the three runs, --plant, --no-tare, bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"

using namespace massid_cli_test;

namespace {

class CliEmulate : public Cli {
 protected:
  std::string puma_params() {
    const std::string data = puma_data();
    const Result r = run({"identify", kPumaUrdf, data, "-o", path("params.json")});
    EXPECT_EQ(r.code, 0) << r;
    return path("params.json");
  }
};

TEST_F(CliEmulate, WritesTraceAndSummaryOfTheThreeRuns) {
  const std::string params = puma_params();
  const Result r = run({"emulate", kPumaUrdf, params, "-o", path("trace.csv"), "--summary",
                        path("summary.json"), "--duration", "1", "--gravity", "0,0,9.80665"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("identified"), std::string::npos) << r;
  const Table trace = read_table(path("trace.csv"));
  EXPECT_EQ(trace.rows.size(), 1000u);
  EXPECT_EQ(trace.header.front(), "t");
  EXPECT_EQ(trace.header.back(), "supervisor");
  const auto j = nlohmann::json::parse(read_file(path("summary.json")));
  for (const char* run : {"identified", "nominal", "none"})
    for (const char* field :
         {"position_error_max_m", "position_error_rms_m", "attitude_error_max_deg",
          "attitude_error_rms_deg", "reference_excursion_m", "reference_excursion_deg",
          "supervisor_stops", "first_stop_s", "stop_reason"})
      EXPECT_TRUE(j[run].contains(field)) << run << " " << field;
  // The compensated runs never stop: no stop time, reason "none", and the
  // identified run's trace shows the supervisor running throughout.
  for (const char* run : {"identified", "nominal"}) {
    EXPECT_EQ(j[run]["supervisor_stops"].get<int>(), 0) << run;
    EXPECT_TRUE(j[run]["first_stop_s"].is_null()) << run;
    EXPECT_EQ(j[run]["stop_reason"], "none") << run;
  }
  const int sup = trace.col("supervisor");
  for (const auto& row : trace.rows) EXPECT_EQ(row[sup], "running") << "t " << row[0];
  // Uncompensated, the supervisor stops it, within the run, and says why.
  EXPECT_GE(j["none"]["supervisor_stops"].get<int>(), 1);
  ASSERT_TRUE(j["none"]["first_stop_s"].is_number());
  EXPECT_GT(j["none"]["first_stop_s"].get<double>(), 0.0);
  EXPECT_LT(j["none"]["first_stop_s"].get<double>(), 1.0);
  ASSERT_TRUE(j["none"]["stop_reason"].is_string());
  const std::string reason = j["none"]["stop_reason"];
  EXPECT_TRUE(reason == "leg limit" || reason == "workspace" || reason == "tracking error")
      << reason;
  EXPECT_NE(r.out.find("supervisor stopped at"), std::string::npos) << r;
  EXPECT_NE(r.out.find("(" + reason + ")"), std::string::npos) << r;
  EXPECT_GT(j["realtime_factor"].get<double>(), 1.0);
  EXPECT_GT(j["control_step_ns"].get<double>(), 0.0);
  // No compensation: the platform runs off, far worse than with it.
  EXPECT_GT(j["none"]["position_error_max_m"].get<double>(),
            10 * j["identified"]["position_error_max_m"].get<double>());
}

TEST_F(CliEmulate, FollowsATrajectoryFile) {
  const std::string params = puma_params();
  const std::string traj =
      file("traj.csv", "t,joint1,joint2,joint3\n0,0,-1.5,1.5\n0.5,0.3,-1.4,1.6\n");
  const Result r = run({"emulate", kPumaUrdf, params, "-o", path("trace.csv"), "--duration", "0.5",
                        "--trajectory", traj, "--gravity", "0,0,9.80665"});
  EXPECT_EQ(r.code, 0) << r;
}

// Parameters identified from noise-free data of the as-built PUMA (0.45 kg
// more than its CAD model, puma260.urdf, which the parameters are of).
class CliEmulateAsBuilt : public CliEmulate {
 protected:
  const std::string as_built = example("puma260/puma260_as_built.urdf");
  std::string as_built_params() {
    Result r = run({"simulate", as_built, kPumaPlan, "-o", path("as_built.csv")});
    EXPECT_EQ(r.code, 0) << r;
    r = run({"identify", kPumaUrdf, path("as_built.csv"), "-o", path("as_built.json")});
    EXPECT_EQ(r.code, 0) << r;
    return path("as_built.json");
  }
  nlohmann::json emulate(const std::string& params, const std::string& duration,
                         const std::vector<std::string>& extra) {
    std::vector<std::string> args{"emulate",     kPumaUrdf,   params,         "-o",
                                  path("t.csv"), "--summary", path("s.json"), "--duration",
                                  duration,      "--gravity", "0,0,9.80665"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return nlohmann::json::parse(read_file(path("s.json")));
  }
  static double pos_max(const nlohmann::json& j, const char* run) {
    return j[run]["position_error_max_m"].get<double>();
  }
};

TEST_F(CliEmulateAsBuilt, PlantIsTheRobotAsBuilt) {
  const std::string params = as_built_params();
  const auto j = emulate(params, "2", {"--plant", as_built});
  // The identified parameters know the extra 0.45 kg; the CAD model does not.
  EXPECT_GT(pos_max(j, "nominal"), 20 * pos_max(j, "identified"))
      << pos_max(j, "nominal") << " vs " << pos_max(j, "identified");
  // Without --plant the CAD model is the robot: now the nominal run is the
  // good one, far better than with the as-built plant.
  const auto cad = emulate(params, "2", {});
  EXPECT_GT(pos_max(cad, "identified"), 10 * pos_max(cad, "nominal"));
  EXPECT_GT(pos_max(j, "nominal"), 10 * pos_max(cad, "nominal"));
}

TEST_F(CliEmulateAsBuilt, NoTareKeepsTheOffsetAtRest) {
  // The as-built parameters on the CAD robot: a mismatch, largely constant at
  // rest, that the tare removes. The exact (nominal) model has nothing to tare,
  // and the uncompensated run is not tared at all.
  const std::string params = as_built_params();
  const auto tared = emulate(params, "1", {});
  const auto raw = emulate(params, "1", {"--no-tare"});
  EXPECT_GT(pos_max(raw, "identified"), 5 * pos_max(tared, "identified"))
      << pos_max(raw, "identified") << " vs " << pos_max(tared, "identified");
  EXPECT_NEAR(pos_max(raw, "nominal"), pos_max(tared, "nominal"), 1e-3 * pos_max(tared, "nominal"));
  EXPECT_EQ(pos_max(raw, "none"), pos_max(tared, "none"));
}

TEST_F(CliEmulate, PlantOfOtherKinematicsIsRejected) {
  const std::string params = puma_params();
  // The PUMA with a longer upper arm (joint3's origin moved).
  std::string text = read_file(kPumaUrdf);
  const std::string origin = "xyz=\"0.198 -0.019 0\"";
  const size_t at = text.find(origin);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, origin.size(), "xyz=\"0.210 -0.019 0\"");
  const std::string longer = file("puma_longer.urdf", text);
  for (const std::string& plant : {longer, example("ur_like/ur_like.urdf")}) {
    expect_input_error(run({"emulate", kPumaUrdf, params, "-o", path("t.csv"), "--duration", "0.5",
                            "--summary", path("s.json"), "--plant", plant}),
                       {plant, "--plant"});
    EXPECT_FALSE(fs::exists(path("t.csv"))) << plant;
    EXPECT_FALSE(fs::exists(path("s.json"))) << plant;
  }
}

TEST_F(CliEmulate, BadInputExitsTwo) {
  const std::string params = puma_params();
  expect_input_error(
      run({"emulate", kPumaUrdf, params, "-o", path("t.csv"), "--spacecraft-inertia", "1,2"}),
      {"--spacecraft-inertia"});
  const std::string traj = file("traj.csv", "t,joint1,joint2\n0,0,0\n");
  expect_input_error(run({"emulate", kPumaUrdf, params, "-o", path("t.csv"), "--trajectory", traj}),
                     {"traj.csv", "joint3"});
  EXPECT_FALSE(fs::exists(path("t.csv")));
}

// A static and a dynamic params file of the same robot (identify and
// identify --dynamic, each from noise-free data of the URDF): both run, and
// the dynamic fit, compensating with its mass part (the motion predictor at
// rest), emulates as faithfully as the static one. Both gravity models are the
// URDF's to the fits' round-off (about 1e-9 of the weight), so what differs
// between the runs is far below the emulator's own error (one-tick delay,
// servo lag): their errors agree within 1 % (a gravity model 10 % off moves
// them by orders of magnitude more: the `nominal` run of an as-built robot).
TEST_F(CliEmulate, StaticAndDynamicParamsOfOneRobotEmulateAlike) {
  const std::string stat = puma_params();
  Result r = run({"design", kPumaUrdf, "--dynamic", "-o", path("traj.csv"), "--duration", "8",
                  "--rate", "100", "--seed", "3", "--evaluations", "200", "--tilt-max", "25",
                  "--gravity", "0,0,9.80665"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"simulate", kPumaUrdf, path("traj.csv"), "-o", path("log.csv"), "--dynamic"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kPumaUrdf, path("log.csv"), "--dynamic", "-o", path("dynamic.json")});
  ASSERT_EQ(r.code, 0) << r;
  nlohmann::json summary[2];
  const std::string files[2] = {stat, path("dynamic.json")};
  for (int k = 0; k < 2; ++k) {
    const std::string out = path("summary" + std::to_string(k) + ".json");
    r = run({"emulate", kPumaUrdf, files[k], "-o", path("trace.csv"), "--summary", out,
             "--duration", "1", "--gravity", "0,0,9.80665"});
    ASSERT_EQ(r.code, 0) << r;
    summary[k] = nlohmann::json::parse(read_file(out));
    EXPECT_EQ(summary[k]["identified"]["supervisor_stops"].get<int>(), 0) << files[k];
  }
  for (const char* field : {"position_error_max_m", "position_error_rms_m",
                            "attitude_error_max_deg", "attitude_error_rms_deg"}) {
    const double s = summary[0]["identified"][field].get<double>();
    const double d = summary[1]["identified"][field].get<double>();
    EXPECT_GT(s, 0.0) << field;
    EXPECT_NEAR(d, s, 0.01 * s) << field;
    // The reference is the same free-floating robot in both.
    EXPECT_EQ(summary[1]["identified"]["reference_excursion_m"],
              summary[0]["identified"]["reference_excursion_m"]);
  }
}

}  // namespace

// A ROS description whose root link is named "world" (MuJoCo's world body):
// emulate runs (it failed with "repeated name in body array"), sizes the
// default spacecraft to the 21 kg arm, and every stop names its limit with
// numbers and the options to change.
TEST_F(CliEmulate, RosUr5WithRootLinkWorldRunsOnASpacecraftSizedToIt) {
  const std::string ur5 = kSource + "/tests/data/robots/ur5_robot.urdf";
  Result r = run({"design", ur5, "-o", path("plan.csv"), "--poses", "24", "--tilt-max", "25",
                  "--candidates", "300"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"simulate", ur5, path("plan.csv"), "-o", path("data.csv")});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", ur5, path("data.csv"), "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"emulate", ur5, path("params.json"), "-o", path("trace.csv"), "--summary",
           path("summary.json"), "--duration", "2"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(read_table(path("trace.csv")).rows.size(), 2000u);
  EXPECT_NE(r.out.find("spacecraft sized to the robot"), std::string::npos) << r;
  const auto j = nlohmann::json::parse(read_file(path("summary.json")));
  // Sized so that the reference stays within half the workspace (25 deg, 0.15 m).
  EXPECT_GT(j["spacecraft_mass_kg"].get<double>(), 50.0);
  for (const char* run : {"identified", "nominal", "none"}) {
    EXPECT_LE(j[run]["reference_excursion_deg"].get<double>(), 12.5) << run;
    EXPECT_LE(j[run]["reference_excursion_m"].get<double>(), 0.075) << run;
  }
  // With the sized spacecraft the compensated runs complete.
  for (const char* run : {"identified", "nominal"})
    EXPECT_EQ(j[run]["supervisor_stops"].get<int>(), 0) << run << "\n" << r;
  // On the old default 50 kg the reference itself turns beyond the workspace:
  // the stop names the limit, its numbers and the options.
  r = run({"emulate", ur5, path("params.json"), "-o", path("trace50.csv"), "--summary",
           path("summary50.json"), "--duration", "2", "--spacecraft-mass", "50"});
  ASSERT_EQ(r.code, 0) << r;
  const auto k = nlohmann::json::parse(read_file(path("summary50.json")));
  EXPECT_GT(k["identified"]["reference_excursion_deg"].get<double>(), 25.0);
  ASSERT_GE(k["identified"]["supervisor_stops"].get<int>(), 1) << r;
  EXPECT_EQ(k["identified"]["stop_reason"], "workspace");
  const std::string detail = k["identified"]["stop_detail"];
  for (const char* piece :
       {"deg from home", "beyond the platform workspace's 25 deg", "--spacecraft-mass",
        "--spacecraft-inertia", "--trajectory", "--platform", "more than the workspace"})
    EXPECT_NE(detail.find(piece), std::string::npos) << piece << "\n" << detail;
  EXPECT_NE(r.out.find("(workspace): braking would end"), std::string::npos) << r;
}

// The published Robotiq 2F-85 gripper: one independent joint and five mimic
// joints (multipliers 1 and -1) that carry most of its moving mass. emulate
// runs end to end and writes its outputs. With the URDF's own parameters (the
// nominal run; the identified ones are the same, from noise-free data) the
// controller's gravity model is exact only if the plant moves every mimic
// joint as massid's model does: the emulated base then tracks the free-floating
// reference within a fraction of a percent, as for robots without mimic joints,
// where a finger moved otherwise would leave a force that drifts the base.
TEST_F(CliEmulate, RobotiqGripperWithMimicJointsRunsEndToEnd) {
  const std::string gripper = kSource + "/tests/data/robots/robotiq_2f_85.urdf";
  Result r = run({"design", gripper, "-o", path("plan.csv"), "--poses", "24", "--tilt-max", "25",
                  "--candidates", "300"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"simulate", gripper, path("plan.csv"), "-o", path("data.csv")});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", gripper, path("data.csv"), "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  // A spacecraft light enough that the 0.4 kg gripper moves it measurably.
  r = run({"emulate", gripper, path("params.json"), "-o", path("trace.csv"), "--summary",
           path("summary.json"), "--duration", "2", "--spacecraft-mass", "2",
           "--spacecraft-inertia", "0.02,0.02,0.02"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(read_table(path("trace.csv")).rows.size(), 2000u);
  const auto j = nlohmann::json::parse(read_file(path("summary.json")));
  for (const char* run : {"identified", "nominal"}) {
    const double excursion = j[run]["reference_excursion_m"].get<double>();
    const double rel_position = j[run]["position_error_max_m"].get<double>() / excursion;
    const double rel_attitude = j[run]["attitude_error_max_deg"].get<double>() /
                                j[run]["reference_excursion_deg"].get<double>();
    EXPECT_EQ(j[run]["supervisor_stops"].get<int>(), 0) << run << "\n" << r;
    EXPECT_GT(excursion, 5e-5) << run;
    EXPECT_LT(rel_position, 0.01) << run << "\n" << r;
    EXPECT_LT(rel_attitude, 0.05) << run << "\n" << r;
  }
  // The reference moves a fraction of a millimetre: the errors are printed in
  // metres beside it, not as a percentage of next to nothing.
  EXPECT_NE(r.out.find("identified  largest error against the reference's excursion: position "),
            std::string::npos)
      << r;
  EXPECT_NE(r.out.find(" m (the reference: only "), std::string::npos) << r;
  // Uncompensated, its 4 N of weight run the platform off.
  EXPECT_GE(j["none"]["supervisor_stops"].get<int>(), 1) << r;

  // A plant whose finger follows its master the other way is another robot.
  std::string text = read_file(gripper);
  const std::string mimic = "<mimic joint=\"finger_joint\" multiplier=\"-1\"";
  const size_t at = text.find(mimic);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, mimic.size(), "<mimic joint=\"finger_joint\" multiplier=\"1\"");
  const std::string other = file("other_gripper.urdf", text);
  expect_input_error(run({"emulate", gripper, path("params.json"), "-o", path("t2.csv"),
                          "--duration", "0.5", "--plant", other}),
                     {other, "--plant", "left_inner_finger", "follows 'finger_joint'"});
  EXPECT_FALSE(fs::exists(path("t2.csv")));
}

// `massid emulate`: trace and summary files, the three runs, bad input.
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
          "supervisor_stops"})
      EXPECT_TRUE(j[run].contains(field)) << run << " " << field;
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

}  // namespace

// A wrist sensor with a five-finger hand whose 36 joints the log lacks
// (issue 29), as a user runs it: simulate, identify and predict with no
// --fixed; identify gives one note and the same params file, byte for byte,
// as with every finger held by --fixed.
#include "cli_support.hpp"
#include "hand_support.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace massid_cli_test {
namespace {

class CliUnloggedJoints : public Cli {};

size_t occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST_F(CliUnloggedJoints, AHandBelowAWristSensorNeedsNoFixedFlags) {
  namespace ht = massid::hand_test;
  const std::string urdf = file("hand.urdf", ht::hand_urdf_text());
  const std::string plan = file("arm.csv", ht::hand_arm_plan(60));
  Result r = run({"simulate", urdf, plan, "-o", path("log.csv"), "--sensor", ht::kHandSensor,
                  "--noise-force", "0.05", "--noise-moment", "0.005", "--sensor-offset",
                  "0.3,-0.2,0.5,0.02,-0.01,0.03"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(occurrences(r.err, "36 joints below the sensor link"), 1u) << r;

  // No --fixed: one note naming how many were held and how to set them otherwise.
  r = run({"identify", urdf, path("log.csv"), "--sensor", ht::kHandSensor, "--offset", "-o",
           path("auto.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(occurrences(r.err, "massid: note: "), 1u) << r;
  EXPECT_EQ(occurrences(r.err, "36 joints below the sensor link 'wrist_3_link'"), 1u) << r;
  EXPECT_NE(r.err.find("--fixed JOINT=VALUE"), std::string::npos) << r;
  const std::string auto_out = r.out;

  // Every finger held by hand, in the model's order, at the same positions.
  const massid::Model hand = massid::load_urdf(urdf, ht::kHandSensor);
  ASSERT_EQ(hand.num_joints(), 36);
  std::vector<std::string> args{"identify", urdf, path("log.csv"),      "--sensor", ht::kHandSensor,
                                "--offset", "-o", path("explicit.json")};
  for (const massid::Joint& j : hand.joints) {
    const auto held = ht::hand_held();
    const auto it =
        std::find_if(held.begin(), held.end(), [&](const auto& h) { return h.first == j.name; });
    ASSERT_NE(it, held.end()) << j.name;
    args.push_back("--fixed");
    args.push_back(fmt::format("{}={}", j.name, it->second));
  }
  r = run(args);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err.find("joints below the sensor link"), std::string::npos) << r;
  EXPECT_EQ(read_file(path("auto.json")), read_file(path("explicit.json")));
  EXPECT_EQ(auto_out.substr(0, auto_out.rfind("wrote ")), r.out.substr(0, r.out.rfind("wrote ")));

  // The params file records the held joints; predict reads them back.
  const json params = json::parse(read_file(path("auto.json")));
  ASSERT_EQ(params["held_joints"].size(), 36u);
  EXPECT_EQ(params["held_joints"]["hand_index_flex3_joint"].get<double>(), 0.15);
  EXPECT_EQ(params["held_joints"]["hand_index_flex2_joint"].get<double>(), 0.0);
  EXPECT_NEAR(params["total_mass"].get<double>(), hand.nominal_total_mass(), 0.02);
  r = run({"predict", urdf, path("auto.json"), path("log.csv"), "-o", path("pred.csv")});
  ASSERT_EQ(r.code, 0) << r;
}

}  // namespace
}  // namespace massid_cli_test

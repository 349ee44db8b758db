// Joints below the sensor link that a log lacks (a hand's fingers under a
// wrist sensor, issue 29): held at their URDF reference position with one
// note, the fit then equal bit for bit to the fit with every one of them held
// explicitly (hold_joints, the CLI's --fixed), in memory and streamed.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "hand_support.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"

namespace massid {
namespace {

using hand_test::hand_held;
using hand_test::hand_joints;
using hand_test::kHandSensor;

// The arm's poses with the wrench of the hand held at its reference
// position (as hold_joints computes it, independently of the unlogged
// joints' step), noise and an offset: a CSV the way a log holds it.
std::string unlogged_hand_log(const Model& held_model, const std::string& path) {
  const std::string plan_path = path + ".plan.csv";
  {
    std::FILE* f = std::fopen(plan_path.c_str(), "w");
    std::fputs(hand_test::hand_arm_plan(60).c_str(), f);
    std::fclose(f);
  }
  const CsvTable plan_table = read_csv(plan_path);
  const Samples plan = read_samples(held_model, plan_table, WrenchColumns::Optional);
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.offset << 0.3, -0.2, 0.5, 0.02, -0.01, 0.03;
  const Eigen::MatrixXd W = simulate_wrenches(held_model, plan, so);
  std::vector<std::string> header = plan_table.header;
  for (const char* w : kWrenchColumns) header.push_back(w);
  std::vector<std::vector<std::string>> rows;
  for (int i = 0; i < plan.size(); ++i) {
    std::vector<std::string> row = plan_table.rows[i];
    for (int k = 0; k < 6; ++k) row.push_back(fmt::format("{:.17g}", W(i, k)));
    rows.push_back(row);
  }
  write_csv(path, header, rows);
  return path;
}

TEST(UnloggedJoints, AHandsFingersAreHeldWithOneNoteAndFitAsIfHeldByHand) {
  const Model hand = load_urdf_string(hand_test::hand_urdf_text(), kHandSensor);
  ASSERT_EQ(hand.num_joints(), 36);  // the 36 finger joints, none logged
  ASSERT_EQ(hand.num_upstream_joints(), 6);
  // Every finger held by hand at its reference, in the model's order (the params file's order).
  std::vector<std::pair<std::string, double>> by_name;
  for (const Joint& j : hand.joints)
    for (const auto& h : hand_held())
      if (h.first == j.name) by_name.push_back(h);
  ASSERT_EQ(by_name.size(), 36u);
  const Model explicit_held = hold_joints(hand, by_name);
  ASSERT_EQ(explicit_held.num_joints(), 0);
  const std::string dir = ::testing::TempDir();
  const std::string log = unlogged_hand_log(explicit_held, dir + "/unlogged_hand.csv");

  // The step: every finger held at its reference (0, or the limit nearest to 0), one note.
  std::optional<Warning> note;
  const CsvTable table = read_csv(log);
  const Model held = hold_unlogged_joints(hand, table.header, "log", {}, &note);
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->message.find("36 joints below the sensor link 'wrist_3_link'"), std::string::npos)
      << note->message;
  EXPECT_EQ(note->message.find("look like joints"), std::string::npos) << note->message;
  EXPECT_EQ(note->hints.front(), (Hint{Hint::Setting::HoldJoints, ""}));
  EXPECT_EQ(held.num_joints(), 0);
  ASSERT_EQ(held.held.size(), 36u);
  for (const auto& joint : hand_held()) {
    const auto& [name, value] = joint;
    const auto it = std::find_if(held.held.begin(), held.held.end(),
                                 [&](const auto& h) { return h.first == joint.first; });
    ASSERT_NE(it, held.held.end()) << name;
    EXPECT_EQ(it->second, value) << name;
  }

  // The fit, streamed from the file and from samples in memory: the same bits as by hand.
  IdentifyRequest r;
  r.offset = true;
  r.keep_samples = false;
  const Identification by_hand_streamed = identify(explicit_held, r, IdentifySource::file(log));
  const Identification by_hand_in_memory =
      identify(explicit_held, r,
               IdentifySource::data(read_samples(explicit_held, table, WrenchColumns::Required)));
  const Identification streamed = identify(held, r, IdentifySource::file(log));
  const Identification in_memory =
      identify(held, r, IdentifySource::data(read_samples(held, table, WrenchColumns::Required)));
  for (const auto& [id, by_hand] :
       {std::pair{&streamed, &by_hand_streamed}, std::pair{&in_memory, &by_hand_in_memory}}) {
    SCOPED_TRACE(id == &streamed ? "streamed" : "in memory");
    ASSERT_EQ(id->summary.value.size(), by_hand->summary.value.size());
    for (int i = 0; i < by_hand->summary.value.size(); ++i) {
      EXPECT_EQ(id->summary.value[i], by_hand->summary.value[i]) << i;
      EXPECT_EQ(id->summary.stddev[i], by_hand->summary.stddev[i]) << i;
    }
    EXPECT_EQ(params_json(id->model, id->base, &id->summary),
              params_json(by_hand->model, by_hand->base, &by_hand->summary));
  }
  const Identification& by_hand = by_hand_streamed;
  // The total mass of 38 links, said in words rather than as 38 terms on one line.
  ASSERT_GE(by_hand.base.total_mass, 0);
  EXPECT_EQ(by_hand.base.params[by_hand.base.total_mass].expression,
            fmt::format("m(all {} links below wrist_3_link, itself included)", hand.num_links()));
  EXPECT_EQ(hand.num_links(), 38);
  // And right: the mass below the sensor is the tool's and the hand's, as the URDF says.
  EXPECT_NEAR(by_hand.summary.value[by_hand.base.total_mass], hand.nominal_total_mass(),
              4 * by_hand.summary.stddev[by_hand.base.total_mass]);
}

TEST(UnloggedJoints, LoggedFingersStayFreeAndMisspelledOnesAreNamed) {
  const Model hand = load_urdf_string(hand_test::hand_urdf_text(), kHandSensor);
  std::vector<std::string> header(std::begin(hand_test::kHandArmJoints),
                                  std::end(hand_test::kHandArmJoints));
  for (const char* w : {"fx", "fy", "fz", "mx", "my", "mz"}) header.push_back(w);
  // One finger logged under its name, one in degrees, one bound by another name,
  // one misspelled, and a column of something else.
  header.push_back("hand_roll_joint");
  header.push_back("hand_thumb_abd_joint_deg");
  header.push_back("idx_abd");
  header.push_back("hand_midle_abd_joint");
  header.push_back("battery_voltage");
  SampleOptions o;
  o.columns.bind = {{"hand_index_abd_joint", "idx_abd"}};
  std::optional<Warning> note;
  const Model held = hold_unlogged_joints(hand, header, "log.csv:1", o, &note);
  EXPECT_EQ(held.num_joints(), 3);
  for (const char* free : {"hand_roll_joint", "hand_thumb_abd_joint", "hand_index_abd_joint"})
    EXPECT_GE(held.find_joint(free), 0) << free;
  EXPECT_EQ(held.held.size(), 33u);
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->message.find("33 joints below"), std::string::npos) << note->message;
  EXPECT_NE(note->message.find("look like joints: hand_midle_abd_joint "), std::string::npos)
      << note->message;
  EXPECT_EQ(note->message.find("battery_voltage"), std::string::npos) << note->message;

  // Every joint logged: the model as it was, no note.
  for (const Joint& j : hand.joints) header.push_back(j.name);
  note = Warning{};
  EXPECT_EQ(hold_unlogged_joints(hand, header, "log.csv:1", {}, &note).num_joints(), 36);
  EXPECT_FALSE(note.has_value());
  // A joint above the sensor without its column is the reader's error, as before.
  header.erase(header.begin());  // shoulder_pan_joint
  const Model all = hold_unlogged_joints(hand, header, "log.csv:1", {}, &note);
  const std::vector<Eigen::VectorXd> columns(header.size(), Eigen::VectorXd::Zero(3));
  EXPECT_THROW(samples_from_columns(all, header, columns, WrenchColumns::Required), InputError);
}

}  // namespace
}  // namespace massid

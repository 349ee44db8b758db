// The massid command-line tool run as a user runs it: exit codes, one-line
// diagnoses naming file, line and column, atomic outputs, and the happy path of
// every command on the examples.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid_cli_test;

const std::string kHeader = "joint1,joint2,joint3,gx,gy,gz\n";
const std::string kRow = "0.1,0.2,0.3,0,0,9.80665\n";

// ---------------------------------------------------------------- bad CSV input

TEST_F(Cli, NanCellNamesFileLineAndColumn) {
  const std::string f = file("nan.csv", kHeader + kRow + "0.1,NaN,0.3,0,0,9.80665\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":3:5:", "'joint2'", "NaN"});
}

TEST_F(Cli, InfCellNamesFileLineAndColumn) {
  const std::string f = file("inf.csv", kHeader + kRow + kRow + "0.1,0.2,-inf,0,0,9.80665\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":4:9:", "'joint3'", "-inf", "finite"});
}

TEST_F(Cli, NonNumericCellNamesFileLineAndColumn) {
  const std::string f = file("text.csv", kHeader + kRow + "0.1,0.2,0.3,0,zero,9.80665\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":3:15:", "'gy'", "'zero' is not a number"});
}

TEST_F(Cli, EmptyCellNamesFileLineAndColumn) {
  const std::string f = file("empty_cell.csv", kHeader + "0.1,,0.3,0,0,9.80665\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":2:5:", "'joint2'", "empty cell"});
}

TEST_F(Cli, NonFiniteWrenchInDataFileIsRejectedByIdentify) {
  Table t = read_table(puma_data());
  t.rows[4][t.col("mx")] = "nan";
  const std::string f = file("bad_data.csv", to_csv(t));
  expect_input_error(run({"identify", kPumaUrdf, f, "-o", path("p.json")}),
                     {f + ":6:", "'mx'", "nan"});
}

// A joint below the sensor link without a column is held at its reference
// position (issue 29), with one note naming it, how to set it otherwise and
// a column that looks like it (a misspelling).
TEST_F(Cli, MissingJointColumnNamesTheJoint) {
  const std::string f =
      file("missing.csv", "# plan\njoint1,joint3,jiont2,gx,gy,gz\n0.1,0.3,0.2,0,0,9.8\n");
  const Result r = run({"simulate", kPumaUrdf, f, "-o", path("out.csv")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err.rfind("massid: note: " + f + ":2: 1 joint below the sensor link", 0), 0u) << r;
  for (const char* piece :
       {"held still at", "(joint2)", "--fixed JOINT=VALUE", "look like joints: jiont2"})
    EXPECT_NE(r.err.find(piece), std::string::npos) << piece << "\n" << r;
}

TEST_F(Cli, MissingGravityColumnsAreNamed) {
  const std::string f = file("nog.csv", "joint1,joint2,joint3,gx\n0.1,0.2,0.3,0\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}), {f + ":1:", "gy,gz"});
  const std::string g = file("nog2.csv", "joint1,joint2,joint3\n0.1,0.2,0.3\n");
  expect_input_error(run({"simulate", kPumaUrdf, g, "-o", path("out.csv")}),
                     {g + ":1:", "gx,gy,gz"});
}

TEST_F(Cli, DataWithoutWrenchIsRejectedByIdentify) {
  expect_input_error(run({"identify", kPumaUrdf, kPumaPlan, "-o", path("p.json")}),
                     {kPumaPlan + ":5:", "fx,fy,fz,mx,my,mz"});
}

TEST_F(Cli, ShortRowNamesFileLineAndColumn) {
  const std::string f = file("short.csv", kHeader + kRow + "0.1,0.2,0.3,0\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":3:14:", "4 fields", "header has 6"});
}

TEST_F(Cli, LongRowNamesFileLineAndColumn) {
  const std::string f = file("long.csv", kHeader + kRow + "0.1,0.2,0.3,0,0,9.8,7\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":3:21:", "7 fields", "header has 6"});
}

TEST_F(Cli, HeaderWithoutRows) {
  const std::string f = file("header_only.csv", "# comment\n\n" + kHeader + "# no rows\n\n");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":3:1:", "no data rows"});
}

TEST_F(Cli, EmptyFile) {
  const std::string f = file("empty.csv", "");
  expect_input_error(run({"simulate", kPumaUrdf, f, "-o", path("out.csv")}),
                     {f + ":1:1:", "empty file"});
  const std::string g = file("comments.csv", "\xEF\xBB\xBF# only a comment\r\n\r\n");
  expect_input_error(run({"identify", kPumaUrdf, g, "-o", path("p.json")}),
                     {g + ":1:1:", "empty file"});
}

TEST_F(Cli, MissingFile) {
  expect_input_error(run({"simulate", kPumaUrdf, path("nope.csv"), "-o", path("out.csv")}),
                     {path("nope.csv"), "cannot open"});
  expect_input_error(run({"model", path("nope.urdf")}), {path("nope.urdf"), "cannot open"});
}

// ---------------------------------------------------------------- bad URDF input

const std::string kXml = "<?xml version=\"1.0\"?>\n";
const std::string kInertial =
    "<inertial><mass value=\"1\"/>"
    "<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";

TEST_F(Cli, MalformedUrdfNamesTheLine) {
  const std::string f = file("broken.urdf", kXml +
                                                "<robot name=\"r\">\n"
                                                "  <link name=\"a\"/>\n"
                                                "  <link name=b/>\n"
                                                "</robot>\n");
  expect_input_error(run({"model", f}), {f + ":4:", "malformed XML"});
  const std::string g = file("unclosed.urdf", kXml +
                                                  "<robot name=\"r\">\n"
                                                  "  <link name=\"a\"/>\n"
                                                  "  <link name=\"b\">\n"
                                                  "</robot>\n");
  expect_input_error(run({"model", g}), {g + ":4:", "malformed XML"});
  const std::string e = file("empty.urdf", "");
  expect_input_error(run({"model", e}), {e + ":1:", "malformed XML"});
}

std::string one_joint_urdf(const std::string& type, const std::string& extra = "") {
  return kXml +
         "<robot name=\"r\">\n"
         "  <link name=\"a\"/>\n"
         "  <joint name=\"j_" +
         type + "\" type=\"" + type +
         "\">\n"
         "    <parent link=\"a\"/><child link=\"b\"/>" +
         extra +
         "\n"
         "  </joint>\n"
         "  <link name=\"b\">" +
         kInertial +
         "</link>\n"
         "</robot>\n";
}

TEST_F(Cli, FloatingJointIsRejected) {
  const std::string f = file("floating.urdf", one_joint_urdf("floating"));
  expect_input_error(run({"model", f}), {f + ":4:", "'j_floating'", "floating"});
}

TEST_F(Cli, PlanarJointIsRejected) {
  const std::string f = file("planar.urdf", one_joint_urdf("planar", "<axis xyz=\"0 0 1\"/>"));
  expect_input_error(run({"model", f}), {f + ":4:", "'j_planar'", "planar"});
}

// Mimic joints (published grippers): they follow their master in model,
// design, simulate, identify and predict; no file has a column for them.
TEST_F(Cli, MimicJointsFollowTheirMasterEndToEnd) {
  const std::string urdf = MASSID_SOURCE_DIR "/tests/data/robots/robotiq_2f_85.urdf";
  const Result m = run({"model", urdf});
  ASSERT_EQ(m.code, 0) << m;
  for (const char* part :
       {"movable joints: 1", "mimic joints: 5", "= -1 x finger_joint", "note: ", "ignored"})
    EXPECT_NE(m.out.find(part), std::string::npos) << part << "\n" << m;
  const Result d = run(
      {"design", urdf, "-o", path("plan.csv"), "--poses", "12", "--tilt-max", "30", "--seed", "2"});
  ASSERT_EQ(d.code, 0) << d;
  const Table plan = read_table(path("plan.csv"));
  EXPECT_GE(plan.col("finger_joint"), 0);
  for (const char* mimic : {"right_outer_knuckle_joint", "left_inner_knuckle_joint"})
    EXPECT_LT(plan.col(mimic), 0) << mimic;
  for (size_t r = 0; r < plan.rows.size(); ++r) {
    EXPECT_GE(plan.num(r, "finger_joint"), 0.0);
    EXPECT_LE(plan.num(r, "finger_joint"), 0.8757);
  }
  ASSERT_EQ(run({"simulate", urdf, path("plan.csv"), "-o", path("data.csv")}).code, 0);
  const Result id = run({"identify", urdf, path("data.csv"), "-o", path("p.json")});
  ASSERT_EQ(id.code, 0) << id;
  const json p = json::parse(read_file(path("p.json")));
  double urdf_mass = 0.0;
  for (const massid::Link& l : massid::load_urdf(urdf).links) urdf_mass += l.mass;
  EXPECT_NEAR(p["total_mass"].get<double>(), urdf_mass, 1e-9 * urdf_mass);
  ASSERT_EQ(run({"predict", urdf, path("p.json"), path("data.csv"), "-o", path("c.csv")}).code, 0);
  const Table c = read_table(path("c.csv"));
  for (size_t r = 0; r < c.rows.size(); ++r)
    for (const char* k : {"fx", "fy", "fz", "mx", "my", "mz"})
      EXPECT_NEAR(c.num(r, std::string(k) + "_comp"), 0.0, 1e-9) << r << k;
  // Holding a mimic joint holds its master where the mimic is at that value.
  const Result held = run({"model", urdf, "--fixed", "right_outer_knuckle_joint=-0.3"});
  ASSERT_EQ(held.code, 0) << held;
  EXPECT_NE(held.out.find("movable joints: 0"), std::string::npos) << held;
}

TEST_F(Cli, MalformedInertialIsRejectedNotTakenAsZero) {
  // urdfdom logs these and goes on with a zero mass: a silently wrong model.
  const std::string head = kXml + "<robot name=\"r\">\n  <link name=\"a\"/>\n" +
                           "  <joint name=\"j\" type=\"fixed\"><parent link=\"a\"/>"
                           "<child link=\"b\"/></joint>\n  <link name=\"b\">\n";
  const std::string tail = "  </link>\n</robot>\n";
  const std::string mass =
      file("mass.urdf", head + "    <inertial><mass value=\"1,5\"/>" + "</inertial>\n" + tail);
  expect_input_error(run({"model", mass}), {mass + ":6:", "'b'", "1,5"});
  const std::string origin =
      file("origin.urdf", head + "    <inertial>\n      <origin xyz=\"0 0\"/>\n" +
                              "      <mass value=\"2\"/></inertial>\n" + tail);
  expect_input_error(run({"model", origin}), {origin + ":7:", "'b'", "0 0"});
  const std::string nomass = file("nomass.urdf", head + "    <inertial/>\n" + tail);
  expect_input_error(run({"model", nomass}), {nomass + ":6:", "'b'", "mass"});
  // A missing <inertia> does not matter to static wrenches: accepted.
  const std::string ok =
      file("ok.urdf", head + "    <inertial><mass value=\"2\"/></inertial>\n" + tail);
  const Result r = run({"model", ok});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("URDF mass 2 kg"), std::string::npos) << r;
}

TEST_F(Cli, UnknownSensorLink) {
  expect_input_error(run({"model", kPumaUrdf, "--sensor", "nolink"}),
                     {kPumaUrdf, "'nolink'", "link1"});
  expect_input_error(
      run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("out.csv"), "--sensor", "nolink"}),
      {"'nolink'"});
}

// ---------------------------------------------------------------- bad params input

TEST_F(Cli, MalformedParamsJsonNamesLineAndColumn) {
  const std::string data = puma_data();
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("p.json")}).code, 0);
  std::string text = read_file(path("p.json"));
  // Drop the comma after "joint1" (line 5 of the pretty-printed file).
  const size_t at = text.find("\"joint1\",");
  ASSERT_NE(at, std::string::npos);
  text.erase(at + 8, 1);
  const std::string bad = file("bad.json", text);
  expect_input_error(run({"predict", kPumaUrdf, bad, data}), {bad + ":6:", "malformed JSON"});
  const std::string bad2 =
      file("bad2.json", "{\n  \"format\": \"massid-params-1\",\n  \"x\": [1,, 2]\n}\n");
  expect_input_error(run({"predict", kPumaUrdf, bad2, data}), {bad2 + ":3:11:", "malformed JSON"});
  const std::string other = file("other.json", "{\"format\": \"something-else\"}\n");
  expect_input_error(run({"predict", kPumaUrdf, other, data}), {other, "massid-params-1"});
}

TEST_F(Cli, ParamsOfAnotherRobotAreRejected) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  ASSERT_EQ(run({"simulate", urdf, example("ur_like/plan.csv"), "-o", path("ur.csv")}).code, 0);
  ASSERT_EQ(run({"identify", urdf, path("ur.csv"), "-o", path("ur.json")}).code, 0);
  const std::string data = puma_data();
  expect_input_error(run({"predict", kPumaUrdf, path("ur.json"), data}),
                     {path("ur.json"), kPumaUrdf});

  // Same link names, other geometry: the base parameters do not match.
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("puma.json")}).code, 0);
  std::string text = read_file(kPumaUrdf);
  const size_t at = text.find("xyz=\"0.198 -0.019 0\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 20, "xyz=\"0.250 -0.019 0\"");
  const std::string other = file("puma_long.urdf", text);
  expect_input_error(run({"predict", other, path("puma.json"), data}),
                     {path("puma.json"), "another robot"});
}

// ---------------------------------------------------------------- bad usage

TEST_F(Cli, BadUsageExits2) {
  const std::vector<std::vector<std::string>> cases = {
      {},
      {"frobnicate"},
      {"model"},
      {"model", kPumaUrdf, "--bogus"},
      {"simulate", kPumaUrdf, kPumaPlan},
      {"simulate", kPumaUrdf, kPumaPlan, "-o"},
      {"simulate", kPumaUrdf, kPumaPlan, "-o", path("x.csv"), "--seed", "abc"},
      {"simulate", kPumaUrdf, kPumaPlan, "-o", path("x.csv"), "--noise-force", "-1"},
      {"simulate", kPumaUrdf, kPumaPlan, "-o", path("x.csv"), "--offset", "1,2,3"},
      {"simulate", kPumaUrdf, kPumaPlan, "-o", path("x.csv"), "--offset", "1,2,3,4,5,x"},
      {"identify", kPumaUrdf, "-o", path("p.json")},
      {"identify", kPumaUrdf, kPumaPlan, "-o", path("p.json"), "--sigma-force", "0"},
      {"predict", kPumaUrdf, path("p.json")},
  };
  for (const auto& args : cases) {
    const Result r = run(args);
    std::string cmd;
    for (const auto& a : args) cmd += " " + a;
    EXPECT_EQ(r.code, 2) << "massid" << cmd << "\n" << r;
    EXPECT_EQ(count_lines(r.err), 1) << "massid" << cmd << "\n" << r;
    EXPECT_EQ(r.err.rfind("massid: error: ", 0), 0u) << "massid" << cmd << "\n" << r;
    EXPECT_EQ(r.out, "") << "massid" << cmd << "\n" << r;
  }
  EXPECT_TRUE(listing().empty());
  // --help and --version are not errors.
  EXPECT_EQ(run({"--help"}).code, 0);
  EXPECT_EQ(run({"model", "--help"}).code, 0);
  const Result v = run({"--version"});
  EXPECT_EQ(v.code, 0);
  EXPECT_NE(v.out.find("massid"), std::string::npos);
}

// ---------------------------------------------------------------- accepted CSV forms

TEST_F(Cli, CrlfAndBomGiveTheSameResults) {
  const std::string plain = puma_data();
  std::string crlf = "\xEF\xBB\xBF";
  {
    std::istringstream in(read_file(kPumaPlan));
    std::string line;
    while (std::getline(in, line)) crlf += line + "\r\n";
  }
  const std::string plan = file("crlf_plan.csv", crlf);
  const Result s = run({"simulate", kPumaUrdf, plan, "-o", path("crlf_data.csv")});
  ASSERT_EQ(s.code, 0) << s;
  EXPECT_EQ(read_file(path("crlf_data.csv")), read_file(plain));

  // A CRLF+BOM data file identifies the same parameters.
  std::string data_crlf = "\xEF\xBB\xBF# data with CRLF\r\n";
  {
    std::istringstream in(read_file(plain));
    std::string line;
    while (std::getline(in, line)) data_crlf += line + "\r\n";
  }
  const std::string data = file("crlf_data2.csv", data_crlf);
  ASSERT_EQ(run({"identify", kPumaUrdf, plain, "-o", path("a.json")}).code, 0);
  const Result id = run({"identify", kPumaUrdf, data, "-o", path("b.json")});
  ASSERT_EQ(id.code, 0) << id;
  EXPECT_EQ(read_file(path("a.json")), read_file(path("b.json")));
}

TEST_F(Cli, CommentsBlankLinesExtraColumnsAndDegrees) {
  // The PUMA plan in degrees for joint1, with comments, blank lines and a text
  // column holding a comma.
  Table t = read_plan(kPumaPlan);
  const int j1 = t.col("joint1");
  ASSERT_GE(j1, 0);
  t.header[j1] = "joint1_deg";
  t.header.push_back("note");
  std::string text = "# degrees\n\n" + join(t.header) + "\n";
  for (size_t r = 0; r < t.rows.size(); ++r) {
    auto row = t.rows[r];
    std::ostringstream deg;
    deg.precision(17);
    deg << std::stod(row[j1]) * 180.0 / std::numbers::pi;
    row[j1] = deg.str();
    row.push_back("\"pose " + std::to_string(r) + ", ok\"");
    text += join(row) + "\n";
    if (r == 3) text += "# a comment\n\n   \n";
  }
  const std::string plan = file("deg_plan.csv", text);
  const Result s = run({"simulate", kPumaUrdf, plan, "-o", path("deg_data.csv")});
  ASSERT_EQ(s.code, 0) << s;
  EXPECT_NE(s.out.find("simulated 30 samples"), std::string::npos) << s;

  const std::string out = read_file(path("deg_data.csv"));
  EXPECT_NE(out.find("\"pose 0, ok\""), std::string::npos);
  EXPECT_NE(out.find("\"pose 29, ok\""), std::string::npos);
  EXPECT_EQ(out.find('#'), std::string::npos);

  // Same wrenches as the radian plan.
  const Table rad = read_table(puma_data());
  const Table deg = read_table(path("deg_data.csv"));
  ASSERT_EQ(rad.rows.size(), 30u);
  ASSERT_EQ(deg.rows.size(), 30u);
  for (size_t r = 0; r < 30; ++r)
    for (const char* k : {"fx", "fy", "fz", "mx", "my", "mz"})
      EXPECT_NEAR(deg.num(r, k), rad.num(r, k), 1e-9) << "row " << r << " " << k;
  // The output's columns: the input's (tilt and note carried), then the wrench.
  const std::string header = out.substr(0, out.find('\n'));
  EXPECT_EQ(header,
            "joint1_deg,joint2,joint3,gx,gy,gz,tilt_x_deg,tilt_y_deg,note,fx,fy,fz,mx,my,mz");

  // predict carries the extra columns too and reads the degrees.
  const Result id = run({"identify", kPumaUrdf, path("deg_data.csv"), "-o", path("p.json")});
  ASSERT_EQ(id.code, 0) << id;
  const Result p =
      run({"predict", kPumaUrdf, path("p.json"), path("deg_data.csv"), "-o", path("pred.csv")});
  ASSERT_EQ(p.code, 0) << p;
  const std::string pred = read_file(path("pred.csv"));
  EXPECT_EQ(pred.substr(0, pred.find('\n')),
            header +
                ",fx_pred,fy_pred,fz_pred,mx_pred,my_pred,mz_pred"
                ",fx_comp,fy_comp,fz_comp,mx_comp,my_comp,mz_comp");
  EXPECT_NE(pred.find("\"pose 17, ok\""), std::string::npos);
}

// ---------------------------------------------------------------- atomic outputs

TEST_F(Cli, FailedCommandsLeaveTheOutputUntouched) {
  const std::string data = puma_data();
  const std::string old = "precious, not to be clobbered\n";
  const std::string bad = file("bad.csv", kHeader + kRow + "0.1,nan,0.3,0,0,9.8\n");
  const std::string bad_data = file("bad_data.csv", kHeader + kRow);

  auto check = [&](const std::string& out_name, const std::vector<std::string>& args, int code) {
    const std::string out = file(out_name, old);
    const auto before = listing();
    const Result r = run(args);
    EXPECT_EQ(r.code, code) << r;
    EXPECT_EQ(read_file(out), old) << out_name;
    EXPECT_EQ(listing(), before) << "a temporary file was left behind";
  };
  check("p.json", {"identify", kPumaUrdf, bad, "-o", path("p.json")}, 2);
  check("p.json", {"identify", kPumaUrdf, bad_data, "-o", path("p.json")}, 2);
  check("p.json", {"identify", kPumaUrdf, data, "-o", path("p.json"), "--offset"}, 3);
  check("p.json", {"identify", path("nope.urdf"), data, "-o", path("p.json")}, 2);
  check("d.csv", {"simulate", kPumaUrdf, bad, "-o", path("d.csv")}, 2);
  check("d.csv", {"simulate", kPumaUrdf, kPumaPlan, "-o", path("d.csv"), "--offset", "1"}, 2);
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("good.json")}).code, 0);
  check("pred.csv", {"predict", kPumaUrdf, path("good.json"), bad, "-o", path("pred.csv")}, 2);

  // An output that cannot be written: exit 2 naming it, no temporary left.
  expect_input_error(run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("no/such/dir.csv")}),
                     {path("no/such/dir.csv"), "cannot write"});
  fs::create_directory(path("a_dir"));
  const auto before = listing();
  expect_input_error(run({"identify", kPumaUrdf, data, "-o", path("a_dir")}),
                     {path("a_dir"), "cannot write"});
  EXPECT_EQ(listing(), before);
}

TEST_F(Cli, SuccessfulWriteReplacesTheOutput) {
  const std::string data = puma_data();
  const std::string fresh = read_file(data);
  file("d.csv", "old content\n");
  file("p.json", "{}\n");
  ASSERT_EQ(run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("d.csv")}).code, 0);
  EXPECT_EQ(read_file(path("d.csv")), fresh);
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("p.json")}).code, 0);
  EXPECT_EQ(json::parse(read_file(path("p.json")))["format"], "massid-params-1");
  EXPECT_EQ(listing(), (std::vector<std::string>{"d.csv", "p.json", "puma_data.csv"}));
  // Readable by others as a normal file would be (mkstemp creates 0600).
  const auto perms = fs::status(path("p.json")).permissions();
  EXPECT_NE(perms & fs::perms::owner_read, fs::perms::none);
  const mode_t mask = umask(0);
  umask(mask);
  if (!(mask & S_IRGRP)) {
    EXPECT_NE(perms & fs::perms::group_read, fs::perms::none);
  }
}

// ---------------------------------------------------------------- exit 3

TEST_F(Cli, OffsetOnLevelAndOneTiltIsUndetermined) {
  const Result r = run({"identify", kPumaUrdf, puma_data(), "-o", path("p.json"), "--offset"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(r.out, "") << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("undetermined"), std::string::npos) << r;
  EXPECT_NE(r.err.find("offset_"), std::string::npos) << r;
  EXPECT_NE(r.err.find("tilt the platform"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(path("p.json")));
  EXPECT_EQ(listing(), std::vector<std::string>{"puma_data.csv"});
}

TEST_F(Cli, LevelOnlyDataAsksForTiltAndTooFewRowsForPoses) {
  // Level rows only: the z moment arm (p9) stays undetermined.
  Table t = read_table(puma_data());
  std::erase_if(t.rows, [&](const auto& row) { return row[t.col("tilt_y_deg")] != "0"; });
  ASSERT_EQ(t.rows.size(), 15u);
  const std::string level = file("level.csv", to_csv(t));
  Result r = run({"identify", kPumaUrdf, level, "-o", path("p.json")});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("p9"), std::string::npos) << r;
  EXPECT_NE(r.err.find("tilt the platform"), std::string::npos) << r;

  t.rows.resize(1);  // 6 equations, 10 unknowns
  const std::string one = file("one.csv", to_csv(t));
  r = run({"identify", kPumaUrdf, one, "-o", path("p.json")});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("more poses"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(path("p.json")));
}

TEST_F(Cli, JointThatNeverMovesIsNamed) {
  for (const std::string joint : {"joint1", "joint3"}) {
    Table t = read_plan(kPumaPlan);
    const int c = t.col(joint);
    ASSERT_GE(c, 0);
    for (auto& row : t.rows) row[c] = "0.5";
    const std::string plan = file("const_" + joint + ".csv", to_csv(t));
    const std::string data = path("const_" + joint + "_data.csv");
    ASSERT_EQ(run({"simulate", kPumaUrdf, plan, "-o", data}).code, 0);
    const Result r = run({"identify", kPumaUrdf, data, "-o", path("p.json")});
    EXPECT_EQ(r.code, 3) << r;
    EXPECT_EQ(count_lines(r.err), 1) << r;
    EXPECT_NE(r.err.find(data), std::string::npos) << r;
    EXPECT_NE(r.err.find("undetermined"), std::string::npos) << r;
    EXPECT_NE(r.err.find("move joint " + joint), std::string::npos) << r;
    EXPECT_FALSE(fs::exists(path("p.json")));
  }
}

// ---------------------------------------------------------------- happy paths

TEST_F(Cli, ModelText) {
  const Result r = run({"model", kPumaUrdf});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err, "");
  for (const char* s : {"sensor link 'sensor'", "measured bodies: 5", "movable joints: 3",
                        "standard parameters: 20", "base parameters: 10", "joint1", "link3",
                        "M    [kg] = m(sensor) + m(base) + m(link1) + m(link2) + m(link3)"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << "\n" << r;
  const Result s = run({"model", kPumaUrdf, "--sensor", "link1"});
  ASSERT_EQ(s.code, 0) << s;
  EXPECT_NE(s.out.find("sensor link 'link1'"), std::string::npos) << s;
  EXPECT_NE(s.out.find("measured bodies: 3"), std::string::npos) << s;
  for (const char* ex :
       {"branching/branching.urdf", "ur_like/ur_like.urdf", "wrist_tool/wrist_tool.urdf"}) {
    const Result e = run({"model", example(ex)});
    EXPECT_EQ(e.code, 0) << ex << "\n" << e;
  }
}

TEST_F(Cli, ModelJson) {
  const Result r = run({"model", kPumaUrdf, "--json"});
  ASSERT_EQ(r.code, 0) << r;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["format"], "massid-params-1");
  EXPECT_EQ(j["sensor_link"], "sensor");
  EXPECT_EQ(j["joints"], json({"joint1", "joint2", "joint3"}));
  ASSERT_EQ(j["base_parameters"].size(), 10u);
  const std::vector<std::string> links{"sensor", "base", "link1", "link2", "link3"};
  bool has_total_mass = false;
  for (const auto& p : j["base_parameters"]) {
    EXPECT_TRUE(p.contains("name") && p.contains("unit") && p.contains("expression")) << p;
    EXPECT_FALSE(p.contains("value")) << p;
    ASSERT_TRUE(p.contains("terms")) << p;
    ASSERT_FALSE(p["terms"].empty()) << p;
    bool all_mass = true;
    for (const auto& t : p["terms"]) {
      EXPECT_NE(std::find(links.begin(), links.end(), t["link"].get<std::string>()), links.end());
      const std::string param = t["param"];
      EXPECT_TRUE(param == "m" || param == "mx" || param == "my" || param == "mz") << t;
      EXPECT_TRUE(t["coef"].is_number()) << t;
      all_mass = all_mass && param == "m" && t["coef"] == 1.0;
    }
    if (all_mass && p["terms"].size() == 5) has_total_mass = true;
  }
  EXPECT_TRUE(has_total_mass) << "no base parameter is the total mass";
  EXPECT_FALSE(j.contains("sensor_offset"));
  const json o = json::parse(run({"model", kPumaUrdf, "--json", "--offset"}).out);
  EXPECT_TRUE(o.contains("sensor_offset"));
  EXPECT_EQ(o["base_parameters"].size(), 10u);
}

TEST_F(Cli, SimulateIdentifyPredictRoundTrip) {
  const std::string data = puma_data();
  const Result id = run({"identify", kPumaUrdf, data, "-o", path("p.json")});
  ASSERT_EQ(id.code, 0) << id;
  EXPECT_EQ(id.err, "");
  EXPECT_NE(id.out.find("total mass: 10.6 kg"), std::string::npos) << id;
  EXPECT_NE(id.out.find("condition number"), std::string::npos) << id;
  EXPECT_NE(id.out.find("residual"), std::string::npos) << id;

  const json p = json::parse(read_file(path("p.json")));
  EXPECT_EQ(p["format"], "massid-params-1");
  EXPECT_EQ(p["samples"], 30);
  EXPECT_EQ(p["gravity_from"], "columns");
  EXPECT_NEAR(p["total_mass"].get<double>(), 10.6, 1e-9);
  ASSERT_EQ(p["base_parameters"].size(), 10u);
  std::map<std::string, double> value;
  for (const auto& b : p["base_parameters"]) {
    ASSERT_TRUE(b.contains("value") && b.contains("std") && b.contains("terms")) << b;
    value[b["name"]] = b["value"];
  }
  // The paper's estimates are the URDF's truth (see puma260.urdf).
  EXPECT_NEAR(value["p1"], 0.158, 1e-9);
  EXPECT_NEAR(value["p3"], 0.382, 1e-9);
  EXPECT_NEAR(value["p9"], -2.445, 1e-9);
  EXPECT_NEAR(value["M"], 10.6, 1e-9);
  EXPECT_FALSE(p.contains("sensor_offset"));
  for (const char* k : {"fx", "fy", "fz", "mx", "my", "mz"})
    EXPECT_LT(p["residual_rms"][k].get<double>(), 1e-9) << k;

  const Result pr = run({"predict", kPumaUrdf, path("p.json"), data, "-o", path("pred.csv")});
  ASSERT_EQ(pr.code, 0) << pr;
  EXPECT_EQ(pr.err, "");
  // Per axis: rms, max and rms as a % of range.
  for (const char* k : {"fx", "fy", "fz", "mx", "my", "mz"}) {
    const size_t at = pr.out.find(std::string("\n  ") + k + " ");
    EXPECT_NE(at, std::string::npos) << k << "\n" << pr;
  }
  EXPECT_NE(pr.out.find("rms"), std::string::npos) << pr;
  EXPECT_NE(pr.out.find("max"), std::string::npos) << pr;
  EXPECT_NE(pr.out.find("range"), std::string::npos) << pr;
  EXPECT_NE(pr.out.find("%"), std::string::npos) << pr;

  const Table in = read_table(data);
  const Table out = read_table(path("pred.csv"));
  ASSERT_EQ(out.rows.size(), in.rows.size());
  for (size_t c = 0; c < in.header.size(); ++c) EXPECT_EQ(out.header[c], in.header[c]);
  for (size_t r = 0; r < in.rows.size(); ++r) {
    for (size_t c = 0; c < in.header.size(); ++c) EXPECT_EQ(out.rows[r][c], in.rows[r][c]);
    for (const char* k : {"fx", "fy", "fz", "mx", "my", "mz"}) {
      const std::string s(k);
      EXPECT_NEAR(out.num(r, s + "_pred"), in.num(r, s), 1e-9) << r << " " << k;
      EXPECT_NEAR(out.num(r, s + "_comp"), 0.0, 1e-9) << r << " " << k;
    }
  }

  // On a plan (no measured wrench): predictions only.
  const Result pp = run({"predict", kPumaUrdf, path("p.json"), kPumaPlan, "-o", path("pp.csv")});
  ASSERT_EQ(pp.code, 0) << pp;
  const Table plan_out = read_table(path("pp.csv"));
  EXPECT_GE(plan_out.col("mz_pred"), 0);
  EXPECT_LT(plan_out.col("fx_comp"), 0);
  EXPECT_NEAR(plan_out.num(0, "fz_pred"), in.num(0, "fz"), 1e-9);
  // Without -o nothing is written.
  const auto before = listing();
  ASSERT_EQ(run({"predict", kPumaUrdf, path("p.json"), data}).code, 0);
  EXPECT_EQ(listing(), before);
}

TEST_F(Cli, EveryExampleRoundTrips) {
  for (const char* ex : {"branching/branching", "ur_like/ur_like", "wrist_tool/wrist_tool"}) {
    const std::string name = fs::path(ex).filename().string();
    const std::string urdf = example(std::string(ex) + ".urdf");
    const std::string plan = fs::path(urdf).parent_path().string() + "/plan.csv";
    const Result s = run({"simulate", urdf, plan, "-o", path(name + ".csv")});
    ASSERT_EQ(s.code, 0) << s;
    const size_t at = s.out.find("total mass ");
    ASSERT_NE(at, std::string::npos) << s;
    const double nominal = std::stod(s.out.substr(at + 11));
    const Result id = run({"identify", urdf, path(name + ".csv"), "-o", path(name + ".json")});
    ASSERT_EQ(id.code, 0) << id;
    const json p = json::parse(read_file(path(name + ".json")));
    EXPECT_NEAR(p["total_mass"].get<double>(), nominal, 1e-5 * nominal) << ex;
    const Result pr = run({"predict", urdf, path(name + ".json"), path(name + ".csv")});
    EXPECT_EQ(pr.code, 0) << pr;
  }
}

TEST_F(Cli, SimulateOffsetNoiseAndSeed) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  const std::string plan = example("ur_like/plan.csv");
  auto sim = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args{"simulate", urdf, plan, "-o", path(name)};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return read_table(path(name));
  };
  const Table clean = sim("clean.csv", {});
  const Table offset = sim("offset.csv", {"--sensor-offset", "1,-2,3.5,0.1,-0.2,0.3"});
  const double off[6] = {1, -2, 3.5, 0.1, -0.2, 0.3};
  const char* const k6[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
  ASSERT_EQ(offset.rows.size(), clean.rows.size());
  for (size_t r = 0; r < clean.rows.size(); ++r)
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(offset.num(r, k6[k]) - clean.num(r, k6[k]), off[k], 1e-9);

  // identify --offset recovers it (this plan tilts in every direction).
  const Result id = run({"identify", urdf, path("offset.csv"), "-o", path("p.json"), "--offset"});
  ASSERT_EQ(id.code, 0) << id;
  const json p = json::parse(read_file(path("p.json")));
  ASSERT_TRUE(p.contains("sensor_offset"));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(p["sensor_offset"]["force"][k].get<double>(), off[k], 1e-9);
    EXPECT_NEAR(p["sensor_offset"]["moment"][k].get<double>(), off[3 + k], 1e-9);
  }
  // predict: fx_pred .. mz_pred is the mechanism's wrench alone (the data
  // without the offset), fx_comp = measured - predicted - offset vanishes.
  ASSERT_EQ(run({"predict", urdf, path("p.json"), path("offset.csv"), "-o", path("c.csv")}).code,
            0);
  const Table comp = read_table(path("c.csv"));
  for (size_t r = 0; r < comp.rows.size(); ++r)
    for (int k = 0; k < 6; ++k) {
      EXPECT_NEAR(comp.num(r, std::string(k6[k]) + "_comp"), 0.0, 1e-9);
      EXPECT_NEAR(comp.num(r, std::string(k6[k]) + "_pred"), clean.num(r, k6[k]), 1e-9);
    }

  // Noise: the right size, and the seed decides it.
  const std::vector<std::string> noise{"--noise-force", "0.5", "--noise-moment", "0.02"};
  auto with = [&](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  const Table n1 = sim("n1.csv", with(noise, {"--seed", "42"}));
  sim("n2.csv", with(noise, {"--seed", "42"}));
  sim("n3.csv", with(noise, {"--seed", "43"}));
  sim("n4.csv", noise);
  sim("n5.csv", noise);
  EXPECT_EQ(read_file(path("n1.csv")), read_file(path("n2.csv")));
  EXPECT_NE(read_file(path("n1.csv")), read_file(path("n3.csv")));
  EXPECT_EQ(read_file(path("n4.csv")), read_file(path("n5.csv")));
  double ss[2] = {0, 0};
  int n[2] = {0, 0};
  for (size_t r = 0; r < clean.rows.size(); ++r)
    for (int k = 0; k < 6; ++k) {
      const double d = n1.num(r, k6[k]) - clean.num(r, k6[k]);
      ss[k / 3] += d * d;
      ++n[k / 3];
    }
  const double sf = std::sqrt(ss[0] / n[0]), sm = std::sqrt(ss[1] / n[1]);
  EXPECT_GT(sf, 0.5 * 0.8);
  EXPECT_LT(sf, 0.5 * 1.2);
  EXPECT_GT(sm, 0.02 * 0.8);
  EXPECT_LT(sm, 0.02 * 1.2);
  // The non-wrench columns are carried unchanged.
  for (size_t r = 0; r < clean.rows.size(); ++r)
    for (const char* c : {"shoulder_pan_joint", "gx", "gz"})
      if (clean.col(c) >= 0) {
        EXPECT_EQ(n1.rows[r][n1.col(c)], clean.rows[r][clean.col(c)]);
      }

  // Noisy data identify fine, with a nonzero standard deviation.
  const Result nid = run({"identify", urdf, path("n1.csv"), "-o", path("n.json")});
  ASSERT_EQ(nid.code, 0) << nid;
  const json nj = json::parse(read_file(path("n.json")));
  EXPECT_GT(nj["base_parameters"][0]["std"].get<double>(), 0.0);
}

TEST_F(Cli, SimulateRepeatHoldsEachPoseForNSamples) {
  const Table plan = read_plan(kPumaPlan);
  ASSERT_EQ(plan.rows.size(), 30u);
  auto sim = [&](const std::string& name, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"simulate", kPumaUrdf, kPumaPlan, "-o", path(name)};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return read_table(path(name));
  };
  const char* const k6[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
  const Table once = sim("once.csv", {"--repeat", "1"});
  EXPECT_EQ(read_file(path("once.csv")), read_file(puma_data()));  // --repeat 1 is the default
  ASSERT_EQ(once.rows.size(), 30u);

  // Noise-free: each plan row three times in order, the copies identical to --repeat 1's row.
  const Table clean = sim("clean.csv", {"--repeat", "3"});
  ASSERT_EQ(clean.header, once.header);
  ASSERT_EQ(clean.rows.size(), 90u);
  for (size_t r = 0; r < 90; ++r) EXPECT_EQ(clean.rows[r], once.rows[r / 3]) << "row " << r;

  // Noisy: the plan's cells carried unchanged, the wrench noisy and different in every copy.
  const double sigma[2] = {0.3, 0.02};
  const Table noisy = sim("noisy.csv", {"--repeat", "3", "--noise-force", "0.3", "--noise-moment",
                                        "0.02", "--seed", "5"});
  ASSERT_EQ(noisy.header, once.header);
  ASSERT_EQ(noisy.rows.size(), 90u);
  double ss[2] = {0, 0};
  for (size_t r = 0; r < 90; ++r) {
    for (size_t c = 0; c < plan.header.size(); ++c) {
      ASSERT_EQ(noisy.header[c], plan.header[c]);
      EXPECT_EQ(noisy.rows[r][c], plan.rows[r / 3][c]) << "row " << r << " " << plan.header[c];
    }
    for (int k = 0; k < 6; ++k) {
      const double d = noisy.num(r, k6[k]) - once.num(r / 3, k6[k]);
      EXPECT_LT(std::abs(d), 6 * sigma[k / 3]) << "row " << r << " " << k6[k];
      ss[k / 3] += d * d;
      if (r % 3 > 0) {
        EXPECT_NE(noisy.rows[r][noisy.col(k6[k])], noisy.rows[r - 1][noisy.col(k6[k])])
            << "row " << r << " " << k6[k];
      }
    }
  }
  // Noise of the requested size in every copy.
  for (int g = 0; g < 2; ++g) {
    const double s = std::sqrt(ss[g] / (90 * 3));
    EXPECT_GT(s, 0.8 * sigma[g]) << g;
    EXPECT_LT(s, 1.2 * sigma[g]) << g;
  }

  // --repeat 0 is bad usage; nothing is written.
  expect_input_error(
      run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("zero.csv"), "--repeat", "0"}),
      {"--repeat"});
  EXPECT_FALSE(fs::exists(path("zero.csv")));
}

TEST_F(Cli, GravityFromForceIsAnnounced) {
  Table t = read_table(puma_data());
  // No gx,gy,gz, nor the plan's tilt columns (they would give gravity).
  for (const char* g : {"gz", "gy", "gx", "tilt_x_deg", "tilt_y_deg"}) {
    const int c = t.col(g);
    if (c < 0) continue;
    t.header.erase(t.header.begin() + c);
    for (auto& row : t.rows) row.erase(row.begin() + c);
  }
  const std::string f = file("nograv.csv", to_csv(t));
  const Result r = run({"identify", kPumaUrdf, f, "-o", path("p.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("gx,gy,gz"), std::string::npos) << r;
  const json p = json::parse(read_file(path("p.json")));
  EXPECT_EQ(p["gravity_from"], "force");
  EXPECT_NEAR(p["total_mass"].get<double>(), 10.6, 1e-9);
}

// massid bench: the figures users size their loop with, as JSON.
TEST_F(Cli, BenchPrintsItsFiguresAsJson) {
  const Result r = run({"bench", kPumaUrdf, "--json", "--rows", "2000"});
  ASSERT_EQ(r.code, 0) << r;
  const json j = json::parse(r.out);
  for (const char* key : {"predict_ns", "predict_dynamic_ns", "regressor_ns", "identify_rows_per_s",
                          "identify_csv_rows_per_s"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j[key].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(j["joints"], 3);
  EXPECT_EQ(j["base_parameters"], 10);
  expect_input_error(run({"bench", kPumaUrdf, "--rows", "5"}), {"--rows"});
}

}  // namespace

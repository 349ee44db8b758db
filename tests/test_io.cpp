// CSV reading and writing, atomic output files, params JSON round trip.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "../src/io/csv_stream.hpp"  // private: read_file_samples, the streamed reader
#include "io/atomic_file.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::string& text) {
  try {
    parse_csv(text, "f.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Csv, AcceptsBomCrlfCommentsBlankLinesAndQuotes) {
  const CsvTable t = parse_csv(
      "\xEF\xBB\xBF# comment\r\na, b ,\"c,d\"\r\n\r\n1, 2 ,\"x\"\"y\"\r\n# x\n3,4,5", "f");
  ASSERT_EQ(t.num_columns(), 3);
  EXPECT_EQ(t.header[1], "b");
  EXPECT_EQ(t.header[2], "c,d");
  ASSERT_EQ(t.num_rows(), 2);
  EXPECT_EQ(t.rows[0][2], "x\"y");
  EXPECT_EQ(t.line[0], 4);
  EXPECT_EQ(t.line[1], 6);
  EXPECT_EQ(t.number(1, 1), 4.0);
}

TEST(Csv, ErrorsNameFileLineAndColumn) {
  EXPECT_EQ(error_of("a,b\n1,2\n3"), "f.csv:3:2: row has 1 fields, the header has 2");
  EXPECT_EQ(error_of("a,b\n"), "f.csv:1:1: header but no data rows");
  EXPECT_EQ(error_of(""), "f.csv:1:1: empty file, no header row");
  EXPECT_EQ(error_of("a,a\n1,2"), "f.csv:1:3: column 'a' appears twice in the header");
  const CsvTable t = parse_csv("a,bb\n1, x1\n1,nan\n1,inf\n1,", "f.csv");
  auto number_error = [&](int r, int c) {
    try {
      t.number(r, c);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(number_error(0, 1), "f.csv:2:4: column 'bb': 'x1' is not a number");
  EXPECT_EQ(number_error(1, 1), "f.csv:3:3: column 'bb': 'nan' is not a finite number");
  EXPECT_EQ(number_error(2, 1), "f.csv:4:3: column 'bb': 'inf' is not a finite number");
  EXPECT_EQ(number_error(3, 1), "f.csv:5:3: column 'bb': empty cell, a number is expected");
}

TEST(Csv, NumbersRoundTripExactly) {
  for (double v : {0.1, -2.445, 1e-300, 9.80665, 1.0 / 3.0, 123456789.123456789})
    EXPECT_EQ(parse_csv("a\n" + format_number(v), "f").number(0, 0), v);
}

// The Python module's columns-by-name path: the same samples as the CSV, and
// errors that name data['column'][row].
TEST(Samples, ColumnsInMemoryReadLikeTheCsv) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const std::string text =
      "joint1_deg,joint2,joint3,fx,fy,fz,mx,my,mz,t,block\n"
      "10,0.5,-0.25,1,2,30,0.1,0.2,0.3,0.0,4\n"
      "-45,0.125,1.5,-1,2,-30,0.4,0.5,0.6,0.5,7\n";
  const Samples csv = read_samples(model, parse_csv(text, "log.csv"), WrenchColumns::Required);
  const std::vector<std::string> names{"joint1_deg", "joint2", "joint3", "fx", "fy",   "fz",
                                       "mx",         "my",     "mz",     "t",  "block"};
  std::vector<Eigen::VectorXd> cols(names.size(), Eigen::VectorXd::Zero(2));
  const double values[2][11] = {{10, 0.5, -0.25, 1, 2, 30, 0.1, 0.2, 0.3, 0.0, 4},
                                {-45, 0.125, 1.5, -1, 2, -30, 0.4, 0.5, 0.6, 0.5, 7}};
  for (int r = 0; r < 2; ++r)
    for (size_t c = 0; c < names.size(); ++c) cols[c][r] = values[r][c];
  const Samples mem = samples_from_columns(model, names, cols, WrenchColumns::Required);
  EXPECT_EQ(mem.q, csv.q);
  EXPECT_EQ(mem.wrench, csv.wrench);
  EXPECT_EQ(mem.gravity, csv.gravity);  // from the force (eq. 37) in both
  EXPECT_TRUE(mem.gravity_from_force);
  EXPECT_EQ(mem.time, csv.time);
  EXPECT_EQ(mem.block, csv.block);
  EXPECT_EQ(mem.line, (std::vector<int>{0, 1}));  // row indices
  EXPECT_EQ(mem.source, "data");

  const auto message = [&](const std::vector<std::string>& n,
                           const std::vector<Eigen::VectorXd>& c) {
    try {
      samples_from_columns(model, n, c, WrenchColumns::Required);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto bad = cols;
  bad[5][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message(names, bad), "data['fz'][1]: nan is not a finite number");
  bad = cols;
  bad[10][0] = 2.5;
  EXPECT_EQ(message(names, bad), "data['block'][0]: '2.5' is not an integer");
  bad = cols;
  bad[3].resize(3);
  EXPECT_EQ(message(names, bad), "data: column 'fx' has 3 rows, column 'joint1_deg' has 2");
  auto dup = names;
  dup[4] = "fx";
  EXPECT_EQ(message(dup, cols), "data: column 'fx' appears twice");
  EXPECT_EQ(message({names.begin() + 1, names.end()}, {cols.begin() + 1, cols.end()}),
            "data: no column for joint 'joint1' (expected 'joint1' or 'joint1_deg')");
}

TEST(AtomicFile, FailureLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = fs::temp_directory_path() / "massid_atomic_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "out.txt").string();
  write_file_atomically(path, "old\n");
  write_file_atomically(path, "new\n");
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "new\n");
  EXPECT_THROW(write_file_atomically((dir / "missing" / "x.txt").string(), "x"), InputError);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(ParamsFile, RoundTripsThroughJson) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/branching/branching.urdf");
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/branching/plan.csv");
  SimulateOptions so;
  so.offset << 1, 2, 3, 0.1, 0.2, 0.3;
  s.wrench = simulate_wrenches(model, s, so);
  const IdentifySummary r = identify(model, base, s);
  const fs::path path = fs::temp_directory_path() / "massid_params_test.json";
  write_file_atomically(path.string(), params_json(model, base, &r));
  const ParamsFile p = read_params(path.string());
  fs::remove(path);
  EXPECT_EQ(p.sensor_link, "sensor");
  EXPECT_EQ(static_cast<int>(p.base_parameters.size()), base.num_mass());
  EXPECT_DOUBLE_EQ(p.total_mass, r.value[base.total_mass]);
  EXPECT_TRUE(p.has_offset);
  const Eigen::VectorXd v = values_in_basis(p, model, base);
  EXPECT_LT((v - r.value).norm(), 1e-12 * r.value.norm());
  // Terms evaluated on the URDF's standard parameters give the identified values.
  const Eigen::VectorXd pi = nominal_standard_parameters(model);
  for (const auto& e : p.base_parameters) {
    double sum = 0.0;
    for (const auto& t : e.terms) {
      int k = 0;
      while (t.param != standard_parameter_kind(k)) ++k;
      sum += t.coef * pi[kParamsPerLink * model.find_link(t.link) + k];
    }
    EXPECT_NEAR(sum, e.value, 1e-9 * std::max(1.0, std::abs(e.value))) << e.name;
  }
}

std::string params_error(const std::string& text) {
  // One file per test: ctest runs the tests of this suite in parallel processes.
  const fs::path path = fs::temp_directory_path() /
                        (std::string("massid_params_error_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json");
  write_file_atomically(path.string(), text);
  std::string what = "no error";
  try {
    read_params(path.string());
  } catch (const InputError& e) {
    what = e.what();
    what.replace(0, path.string().size(), "f.json");
  }
  fs::remove(path);
  return what;
}

TEST(ParamsFile, NumberTooLargeForADoubleIsMalformedJsonWithItsPosition) {
  // Regression (found by fuzz_params): nlohmann reports the overflow as
  // out_of_range, which escaped as an internal error without a position.
  EXPECT_EQ(params_error("{\"format\": \"massid-params-1\",\n \"total_mass\": 1e400}"),
            "f.json:2:20: malformed JSON: number overflow parsing '1e400'");
  EXPECT_EQ(params_error("{\"format\": \"massid-params-1\",\n \"total_mass\": 1e400"),
            "f.json:2:20: malformed JSON: number overflow parsing '1e400'");
}

TEST(ParamsFile, SampleCountMustBeANonNegativeInt) {
  // Regression (found by fuzz_params): a double out of int's range was cast to
  // int (UB); a fraction was silently truncated.
  const std::string head =
      "{\"format\": \"massid-params-1\", \"sensor_link\": \"s\", \"joints\": [], "
      "\"total_mass\": 1, \"base_parameters\": [], \"samples\": ";
  EXPECT_EQ(params_error(head + "1e300}"),
            "f.json: \"samples\" must be a non-negative integer, not 1e+300");
  EXPECT_EQ(params_error(head + "2.5}"),
            "f.json: \"samples\" must be a non-negative integer, not 2.5");
  EXPECT_EQ(params_error(head + "-1}"),
            "f.json: \"samples\" must be a non-negative integer, not -1");
  EXPECT_EQ(params_error(head + "30}"), "no error");
}

// The level gravity that tilt columns turn, the same in every reader (a CSV
// table, columns in memory, the streamed file): the root gravity turned into
// the sensor frame by the fixed joint above the sensor link (here 180 degrees
// about x: level is 0,0,+g), or SampleOptions::level_gravity when given. The
// old readers took the root gravity 0,0,-g as the sensor frame's level
// gravity: every gravity upside down.
TEST(SamplesLevelGravity, TiltColumnsTurnTheRootGravityThroughFixedJoints) {
  const std::string urdf = R"(<robot name="flipped"><link name="base"/>
    <joint name="mount" type="fixed"><parent link="base"/><child link="ft"/>
      <origin xyz="0 0 0.3" rpy="3.141592653589793 0 0"/></joint>
    <link name="ft"/>
    <joint name="j1" type="revolute"><parent link="ft"/><child link="link1"/><axis xyz="0 0 1"/>
      <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    <link name="link1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  </robot>)";
  const Model model = load_urdf_string(urdf, "ft");
  const double tx = 20.0, ty = -10.0;
  const std::string text =
      "j1,tilt_x_deg,tilt_y_deg,fx,fy,fz,mx,my,mz\n0.5,20,-10,0,0,9.8,0,0,0\n0.1,0,0,0,0,9.8,0,0,"
      "0\n";
  const auto turned = [&](const Eigen::Vector3d& level, double x_deg, double y_deg) {
    const double k = std::numbers::pi / 180;
    return Eigen::Vector3d((Eigen::AngleAxisd(x_deg * k, Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(y_deg * k, Eigen::Vector3d::UnitY()))
                               .toRotationMatrix()
                               .transpose() *
                           level);
  };
  const Eigen::Vector3d up(0, 0, kStandardGravity);
  const std::string path = (fs::temp_directory_path() / "massid_level_gravity.csv").string();
  {
    std::ofstream out(path);
    out << text;
  }
  const std::vector<std::string> names{"j1", "tilt_x_deg", "tilt_y_deg", "fx", "fy",
                                       "fz", "mx",         "my",         "mz"};
  std::vector<Eigen::VectorXd> cols(names.size(), Eigen::VectorXd::Zero(2));
  const CsvTable table = parse_csv(text, "log.csv");
  for (int r = 0; r < 2; ++r)
    for (size_t c = 0; c < names.size(); ++c) cols[c][r] = std::stod(table.rows[r][c]);
  for (const std::optional<Eigen::Vector3d>& given :
       {std::optional<Eigen::Vector3d>{},
        std::optional<Eigen::Vector3d>{Eigen::Vector3d(1, 2, 3)}}) {
    SampleOptions o;
    o.level_gravity = given;
    const Eigen::Vector3d level = given ? *given : up;
    const Samples csv = read_samples(model, table, WrenchColumns::Required, o);
    const Samples mem =
        samples_from_columns(model, names, cols, WrenchColumns::Required, "data", o);
    const Samples streamed = detail::read_file_samples(model, path, 10, o);
    ASSERT_EQ(csv.gravity.rows(), 2);
    EXPECT_LT((csv.gravity.row(0).transpose() - turned(level, tx, ty)).norm(), 1e-12);
    EXPECT_LT((csv.gravity.row(1).transpose() - level).norm(), 1e-12);
    EXPECT_EQ(mem.gravity, csv.gravity);
    EXPECT_EQ(streamed.gravity, csv.gravity);
  }
  // Given for a file with gx,gy,gz: unused, an error.
  SampleOptions o;
  o.level_gravity = up;
  const std::string with_g = "j1,gx,gy,gz,fx,fy,fz,mx,my,mz\n0.5,0,0,9.8,0,0,9.8,0,0,0\n";
  try {
    read_samples(model, parse_csv(with_g, "g.csv"), WrenchColumns::Required, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("g.csv:1: a level gravity is given, but the file has no "
                                         "tilt columns"),
              std::string::npos)
        << e.what();
    EXPECT_EQ(e.hints(), (std::vector<Hint>{{Hint::Setting::LevelGravity, ""}}));
  }
  // The sensor link below a movable joint (j1 above link1) without its column:
  // no level gravity follows from the root gravity; given, it is used.
  const Model wrist = load_urdf_string(urdf, "link1");
  const std::string tilt_only = "tilt_x_deg,tilt_y_deg,fx,fy,fz,mx,my,mz\n20,-10,0,0,9.8,0,0,0\n";
  try {
    read_samples(wrist, parse_csv(tilt_only, "w.csv"), WrenchColumns::Required);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("w.csv:1: tilt_x_deg,tilt_y_deg turn the level gravity "
                                         "in the sensor frame, and sensor link 'link1' is below "
                                         "movable joints (j1)"),
              std::string::npos)
        << e.what();
  }
  const Samples given =
      read_samples(wrist, parse_csv(tilt_only, "w.csv"), WrenchColumns::Required, o);
  EXPECT_LT((given.gravity.row(0).transpose() - turned(up, tx, ty)).norm(), 1e-12);
  fs::remove(path);
}

// Without gravity columns gravity is taken along the force: a row without
// force is refused by every reader (a CSV table, columns in memory, the
// streamed file) with the one message, naming its line (row in memory), and
// the integer test of a block cell is the one is_block_number.
TEST(Samples, AZeroForceWithoutGravityIsRefusedAlikeByEveryReader) {
  const Model model = load_urdf_string(R"(<robot name="r"><link name="ft"/>
    <joint name="j1" type="revolute"><parent link="ft"/><child link="link1"/><axis xyz="0 0 1"/>
      <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    <link name="link1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  </robot>)",
                                       "ft");
  const std::string text = "j1,fx,fy,fz,mx,my,mz\n0.5,0,0,9.8,0,0,0\n# note\n0.1,0,0,0,0,0,0\n";
  const std::string path = (fs::temp_directory_path() / "massid_zero_force.csv").string();
  std::ofstream(path) << text;
  const std::string why =
      ": zero force: no gx,gy,gz columns and no force to take the gravity direction from";
  const auto error = [](const auto& read) -> std::string {
    try {
      read();
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error([&] { read_samples(model, parse_csv(text, "z.csv"), WrenchColumns::Required); }),
            "z.csv:4" + why);
  std::vector<Eigen::VectorXd> cols(7, Eigen::VectorXd::Zero(2));
  cols[0] << 0.5, 0.1;
  cols[3] << 9.8, 0.0;
  EXPECT_EQ(error([&] {
              samples_from_columns(model, {"j1", "fx", "fy", "fz", "mx", "my", "mz"}, cols,
                                   WrenchColumns::Required);
            }),
            "data row 1" + why);
  EXPECT_EQ(error([&] { detail::read_file_samples(model, path, 10, {}); }), path + ":4" + why);
  fs::remove(path);
  for (const double b : {0.0, -3.0, 1e9, -1e9}) EXPECT_TRUE(detail::is_block_number(b)) << b;
  for (const double b : {0.5, 1e9 + 1, -2.25, std::numeric_limits<double>::infinity()})
    EXPECT_FALSE(detail::is_block_number(b)) << b;
  cols.push_back(Eigen::Vector2d(1.0, 2.5));
  cols[4] << 0.0, 0.0;
  cols[3] << 9.8, 9.8;
  EXPECT_EQ(error([&] {
              samples_from_columns(model, {"j1", "fx", "fy", "fz", "mx", "my", "mz", "block"}, cols,
                                   WrenchColumns::Required);
            }),
            "data['block'][1]: '2.5' is not an integer");
}

}  // namespace
}  // namespace massid

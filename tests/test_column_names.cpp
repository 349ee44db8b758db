// Columns named otherwise (read_samples.hpp's ColumnNames, column_map.cpp):
// recorders' spellings of the wrench and ROLE=NAME bindings give the very
// numbers the canonical names give; bad bindings, ambiguous spellings and a
// missing wrench are errors that list what the file has; a static fit ignores
// an IMU's ax,ay,az.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "column_spellings.hpp"
#include "io/column_map.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/predict_log.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "massid/live/identified_model.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

namespace fs = std::filesystem;

const std::string kColumnsRobot = MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf";
const std::string kColumnsPlan = MASSID_SOURCE_DIR "/examples/puma260/holdout.csv";

const std::vector<std::vector<std::string>>& kColumnSpellings = massid_test::kWrenchSpellings;

class ColumnNamesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("massid_columns_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    model_ = load_urdf(kColumnsRobot);
    // The example plan (three gravity directions) with noisy wrenches and an offset.
    const CsvTable plan = read_csv(kColumnsPlan);
    SimulateOptions o;
    o.noise_force = 0.05;
    o.noise_moment = 0.005;
    o.offset = test::kOffset;
    o.seed = 7;
    const Eigen::MatrixXd W =
        simulate_wrenches(model_, read_samples(model_, plan, WrenchColumns::Optional), o);
    header_ = plan.header;
    rows_ = plan.rows;
    for (const char* w : kWrenchColumns) header_.push_back(w);
    for (size_t r = 0; r < rows_.size(); ++r)
      for (int k = 0; k < 6; ++k) rows_[r].push_back(format_number(W(static_cast<int>(r), k)));
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // The log with its wrench columns named `wrench` (fx..mz order) and, with
  // `imu`, the columns ax,ay,az of an IMU (in g, gravity included).
  std::string log(const std::string& name, const std::vector<std::string>& wrench,
                  bool imu = false) const {
    std::vector<std::string> header = header_;
    std::copy(wrench.begin(), wrench.end(), header.end() - 6);
    std::vector<std::vector<std::string>> rows = rows_;
    if (imu) {
      for (const char* a : {"ax", "ay", "az"}) header.push_back(a);
      for (auto& row : rows)
        for (const char* v : {"0.01", "-0.02", "1.003"}) row.push_back(v);
    }
    const std::string path = (dir_ / name).string();
    write_csv(path, header, rows);
    return path;
  }
  std::string canonical() const {
    return log("canonical.csv", {"fx", "fy", "fz", "mx", "my", "mz"});
  }

  Identification identified(const std::string& path, ColumnNames names = {},
                            bool keep = false) const {
    IdentifyRequest r;
    r.offset = true;
    r.columns = std::move(names);
    r.keep_samples = keep;
    return identify(model_, r, IdentifySource::file(path));
  }

  fs::path dir_;
  Model model_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

// Bit for bit: the same values, standard deviations and residuals.
void expect_same_fit(const IdentifySummary& a, const IdentifySummary& b, const std::string& what) {
  ASSERT_EQ(a.value.size(), b.value.size()) << what;
  for (Eigen::Index i = 0; i < a.value.size(); ++i) {
    EXPECT_EQ(a.value[i], b.value[i]) << what << " parameter " << i;
    EXPECT_EQ(a.stddev[i], b.stddev[i]) << what << " parameter " << i;
  }
  for (int k = 0; k < 6; ++k) EXPECT_EQ(a.residual_rms[k], b.residual_rms[k]) << what;
  EXPECT_EQ(a.samples, b.samples) << what;
}

TEST_F(ColumnNamesTest, EveryCommonSpellingIdentifiesAsTheCanonicalNames) {
  const Identification ref = identified(canonical());
  // The fit is a real one: the offsets come out near the planted ones.
  const Eigen::Index n = ref.summary.value.size();
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(ref.summary.value[n - 6 + k], test::kOffset[k],
                5 * ref.summary.stddev[n - 6 + k] + 1e-9);
  EXPECT_EQ(column_note(model_, header_, "canonical.csv:1", WrenchColumns::Required, {}), "");
  for (size_t s = 0; s < kColumnSpellings.size(); ++s) {
    const std::string path = log("spelled" + std::to_string(s) + ".csv", kColumnSpellings[s]);
    expect_same_fit(identified(path).summary, ref.summary, kColumnSpellings[s][3]);
    // Streamed and in memory alike (the robust fit reads the file whole).
    IdentifyRequest r;
    r.offset = true;
    r.robust = true;
    r.keep_samples = false;
    IdentifyRequest rc = r;
    expect_same_fit(identify(model_, r, IdentifySource::file(path)).summary,
                    identify(model_, rc, IdentifySource::file(canonical())).summary,
                    "robust " + kColumnSpellings[s][3]);
    // The note names what was read as what.
    const std::string note = file_column_note(model_, path, SampleOptions{});
    EXPECT_NE(note.find(kColumnSpellings[s][3] + " as mx"), std::string::npos) << note;
    if (s > 0) {
      EXPECT_NE(note.find(kColumnSpellings[s][0] + " as fx"), std::string::npos) << note;
    }
  }
}

TEST_F(ColumnNamesTest, BindingsReadColumnsOfAnyName) {
  const Identification ref = identified(canonical());
  const std::vector<std::string> odd = {"F1", "F2", "F3", "M1", "M2", "M3"};
  const std::string path = log("odd.csv", odd);
  ColumnNames names;
  for (int k = 0; k < 6; ++k) names.bind.emplace_back(kWrenchColumns[k], odd[k]);
  expect_same_fit(identified(path, names).summary, ref.summary, "bound");
  // A partial binding beside the canonical names: mx..mz from tx..tz, the
  // canonical mx..mz ignored (here they hold the torque with its sign flipped),
  // and the joints from columns q1..q3.
  std::vector<std::string> header = header_;
  std::vector<std::vector<std::string>> rows = rows_;
  const size_t m0 = header_.size() - 3;  // mx
  for (const char* t : {"tx", "ty", "tz"}) header.push_back(t);
  for (int j = 0; j < 3; ++j) header[j] = "q" + std::to_string(j + 1);
  for (auto& row : rows)
    for (size_t k = 0; k < 3; ++k) {
      row.push_back(row[m0 + k]);
      std::string& cell = row[m0 + k];
      cell = cell[0] == '-' ? cell.substr(1) : "-" + cell;
    }
  const std::string both = (dir_ / "both.csv").string();
  write_csv(both, header, rows);
  ColumnNames torque;
  torque.bind = {{"mx", "tx"},     {"my", "ty"},     {"mz", "tz"},
                 {"joint1", "q1"}, {"joint2", "q2"}, {"joint3", "q3"}};
  expect_same_fit(identified(both, torque).summary, ref.summary, "mx=tx");
  const std::string note = file_column_note(model_, both, [&] {
    SampleOptions o;
    o.columns = torque;
    return o;
  }());
  EXPECT_NE(note.find("tx as mx"), std::string::npos) << note;
  EXPECT_NE(note.find("mx (bound to 'tx' instead)"), std::string::npos) << note;
}

std::string error_of(const std::function<void()>& f, std::vector<Hint>* hints = nullptr) {
  try {
    f();
  } catch (const InputError& e) {
    if (hints) *hints = e.hints();
    return e.what();
  }
  return "no error";
}

TEST_F(ColumnNamesTest, BadBindingsAreErrorsNamingTheBinding) {
  const std::string path = canonical();
  const auto with = [&](std::vector<std::pair<std::string, std::string>> bind) {
    ColumnNames names;
    names.bind = std::move(bind);
    return error_of([&] { identified(path, names); });
  };
  const std::string unknown = with({{"torque_x", "mx"}});
  EXPECT_NE(unknown.find(path + ":1: 'torque_x=mx' binds an unknown role 'torque_x'"),
            std::string::npos)
      << unknown;
  EXPECT_NE(unknown.find("joint1"), std::string::npos) << unknown;
  const std::string absent = with({{"mx", "tx"}});
  EXPECT_NE(absent.find("no column 'tx' to read as 'mx': the header has joint1,"),
            std::string::npos)
      << absent;
  const std::string twice = with({{"mx", "fx"}, {"mx", "fy"}});
  EXPECT_NE(twice.find("role 'mx' is bound twice"), std::string::npos) << twice;
  const std::string two_roles = with({{"mx", "fx"}, {"my", "fx"}});
  EXPECT_NE(two_roles.find("column 'fx' is bound to two roles"), std::string::npos) << two_roles;
}

TEST_F(ColumnNamesTest, TwoSpellingsOfOneRoleAreRefusedNamingBoth) {
  std::vector<std::string> header = header_;
  std::vector<std::vector<std::string>> rows = rows_;
  std::copy(kColumnSpellings[1].begin(), kColumnSpellings[1].end(), header.end() - 6);  // Fx..Tz
  header.push_back("force_x");
  for (auto& row : rows) row.push_back(row[header_.size() - 6]);
  const std::string path = (dir_ / "ambiguous.csv").string();
  write_csv(path, header, rows);
  std::vector<Hint> hints;
  const std::string e = error_of([&] { identified(path); }, &hints);
  EXPECT_NE(e.find(path + ":1: columns 'Fx' and 'force_x' could both be fx"), std::string::npos)
      << e;
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_EQ(hints[0].setting, Hint::Setting::Columns);
  EXPECT_EQ(hints[0].value, "fx=Fx");
  // Saying which resolves it, to the canonical numbers.
  ColumnNames names;
  names.bind = {{"fx", "force_x"}};
  expect_same_fit(identified(path, names).summary, identified(canonical()).summary, "fx=force_x");
}

TEST_F(ColumnNamesTest, AMissingWrenchListsTheHeaderAndProposesTheBinding) {
  const std::vector<std::string> odd = {"Kraft X", "Kraft Y", "Kraft Z", "Fx2", "M_y", "torque"};
  const std::string path = log("odd.csv", odd);
  std::vector<Hint> hints;
  const std::string e = error_of([&] { identified(path); }, &hints);
  EXPECT_NE(e.find(path + ":1: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed, and "
                          "the header has joint1,joint2,joint3,gx,gy,gz"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("Kraft X"), std::string::npos) << e;
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_EQ(hints[0].setting, Hint::Setting::Columns);
  EXPECT_EQ(hints[0].value, "fx=NAME,fy=NAME,fz=NAME,mx=NAME,my=NAME,mz=NAME");
  // Only part of the wrench spelled (the force): not read, and the proposal
  // fills in what was recognised.
  const std::string half = log("half.csv", {"Fx", "Fy", "Fz", "a", "b", "c"});
  const std::string h = error_of([&] { identified(half); }, &hints);
  EXPECT_NE(h.find("no measured wrench"), std::string::npos) << h;
  ASSERT_EQ(hints.size(), 1u);
  EXPECT_EQ(hints[0].value, "fx=Fx,fy=Fy,fz=Fz,mx=NAME,my=NAME,mz=NAME");
}

TEST_F(ColumnNamesTest, PredictReadsRosNamesAndNeverDropsTheWrenchSilently) {
  const Identification ident = identified(canonical());
  const IdentifiedModel im = IdentifiedModel::from_identification(ident);
  const LogPrediction ref = predict_log(im, read_csv(canonical()), "canonical.csv");
  ASSERT_TRUE(ref.has_wrench());
  EXPECT_EQ(ref.column_note, "");
  const std::string ros = log("ros.csv", kColumnSpellings[4]);
  const LogPrediction lp = predict_log(im, read_csv(ros), "ros.csv");
  ASSERT_TRUE(lp.has_wrench());
  ASSERT_EQ(lp.compensated.rows(), ref.compensated.rows());
  EXPECT_TRUE((lp.compensated.array() == ref.compensated.array()).all());
  EXPECT_NE(lp.column_note.find("/ft_sensor/wrench/torque/z as mz"), std::string::npos)
      << lp.column_note;
  // Names not recognised: the prediction goes on, the note says the wrench
  // was not found and lists the columns not read.
  const std::string odd = log("odd.csv", {"A", "B", "C", "D", "E", "F"});
  const LogPrediction none = predict_log(im, read_csv(odd), "odd.csv");
  EXPECT_FALSE(none.has_wrench());
  EXPECT_NE(none.column_note.find("no measured wrench"), std::string::npos) << none.column_note;
  EXPECT_NE(none.column_note.find("ignored: A, B, C, D, E, F"), std::string::npos)
      << none.column_note;
}

TEST_F(ColumnNamesTest, AStaticFitIgnoresAnImusAccelerationsAndSaysWhy) {
  const Identification ref = identified(canonical());
  const std::string path = log("imu.csv", {"fx", "fy", "fz", "mx", "my", "mz"}, true);
  expect_same_fit(identified(path).summary, ref.summary, "imu");
  SampleOptions at_rest;
  at_rest.sensor_motion = false;
  const std::string note = file_column_note(model_, path, at_rest);
  EXPECT_NE(note.find("ignored: ax, ay, az (the sensor frame's motion in part, without "
                      "wx,wy,wz,dwx,dwy,dwz: a static fit needs none"),
            std::string::npos)
      << note;
  // Read for motion, the same columns are an error that says how they would be read.
  const std::string e =
      error_of([&] { read_samples(model_, read_csv(path), WrenchColumns::Required); });
  EXPECT_NE(e.find("column(s) wx,wy,wz,dwx,dwy,dwz missing"), std::string::npos) << e;
  EXPECT_NE(e.find("acceleration without gravity, m/s^2"), std::string::npos) << e;
}

TEST_F(ColumnNamesTest, CompensateBindsAStreamHeaderTheSameWay) {
  const Identification ident = identified(canonical());
  const IdentifiedModel im = IdentifiedModel::from_identification(ident);
  std::string header;
  for (size_t c = 0; c < header_.size(); ++c) {
    const std::string n =
        c + 6 >= header_.size() ? kColumnSpellings[2][c + 6 - header_.size()] : header_[c];
    header += (c ? "," : "") + n;
  }
  Compensator spelled(im, header, "stdin");
  Compensator plain(im, fmt::format("{}", fmt::join(header_, ",")), "stdin");
  EXPECT_NE(spelled.note().find("torque_x as mx"), std::string::npos) << spelled.note();
  EXPECT_EQ(plain.note(), "");
  for (size_t r = 0; r < rows_.size(); ++r) {
    const std::string line = fmt::format("{}", fmt::join(rows_[r], ","));
    spelled.compensate(line, static_cast<int>(r) + 2);
    plain.compensate(line, static_cast<int>(r) + 2);
    EXPECT_TRUE((spelled.compensated().array() == plain.compensated().array()).all()) << r;
  }
}

TEST(WrenchSpelling, TheTableOfRecordersSpellings) {
  using detail::wrench_spelling;
  for (const auto& [name, role] : std::vector<std::pair<std::string, int>>{
           {"Fx", 0},
           {"FY", 1},
           {"tz", 5},
           {"Tx", 3},
           {"Mz", 5},
           {"force_y", 1},
           {"Torque_Z", 5},
           {"moment.x", 3},
           {"field.wrench.force.z", 2},
           {"/ft/wrench/torque/y", 4},
           {"/robot/ft_sensor/wrench/force/x", 0},
           {"wrench.torque.x", 3},
           // not spellings: the canonical names, other quantities, suffixed columns
           {"fx", -1},
           {"mz", -1},
           {"fx_pred", -1},
           {"force", -1},
           {"ax", -1},
           {"t", -1},
           {"/imu/linear_acceleration/x", -1},
           {"force_w", -1},
           {"field.header.stamp", -1}})
    EXPECT_EQ(wrench_spelling(name), role) << name;
}

}  // namespace
}  // namespace massid

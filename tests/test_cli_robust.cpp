// identify on spoiled and drifting logs, as a user runs it: the warning names
// the spoiled lines, --robust rejects them and records them in the params
// file, --drift needs its column and says so.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"

namespace {

using namespace massid_cli_test;

class CliRobust : public Cli {
 protected:
  // PUMA data, 5 samples per pose with noise; rows 7 and 40 (file lines 8
  // and 41) get a 4 N bump on fx.
  std::string spoiled_puma() {
    const std::string data =
        puma_data({"--noise-force", "0.05", "--noise-moment", "0.005", "--repeat", "5"});
    Table t = read_table(data);
    for (int r : {6, 39}) t.rows[r][t.col("fx")] = std::to_string(t.num(r, "fx") + 4.0);
    return file("spoiled.csv", to_csv(t));
  }
};

TEST_F(CliRobust, IdentifyWarnsAboutImplausibleSamplesByLine) {
  const std::string data = spoiled_puma();
  const Result r = run({"identify", kPumaUrdf, data, "-o", path("p.json")});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("massid: warning: "), std::string::npos) << r;
  EXPECT_NE(r.err.find("2 sample(s)"), std::string::npos) << r;
  // The library's words, the CLI's option as the hint.
  EXPECT_NE(r.err.find("or let the robust fit reject them (--robust)\n"), std::string::npos) << r;
  for (const char* line : {"8 (d = ", "41 (d = "})
    EXPECT_NE(r.err.find(line), std::string::npos) << r;
  const auto j = nlohmann::json::parse(read_file(path("p.json")));
  EXPECT_EQ(j["outliers"]["method"], "reported");
  EXPECT_EQ(j["outliers"]["count"], 2);
}

// Ten samples for ten unknowns: the library's words, the CLI's options as the
// hints (the library's text names none).
TEST_F(CliRobust, FewSamplesAskForTheSensorsNoiseByItsOptions) {
  Table t = read_table(puma_data({"--noise-force", "0.05", "--noise-moment", "0.005"}));
  std::vector<std::vector<std::string>> every_third;
  for (std::size_t r = 2; r < t.rows.size(); r += 3) every_third.push_back(t.rows[r]);
  t.rows = every_third;
  const Result r = run({"identify", kPumaUrdf, file("few.csv", to_csv(t)), "-o", path("p.json")});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("massid: warning: "), std::string::npos) << r;
  EXPECT_NE(r.err.find("or give the sensor's noise (--sigma-force; --sigma-moment)\n"),
            std::string::npos)
      << r;
}

// A clean log is streamed without per-sample residuals: its params file says
// which test ran (the largest residual of each axis against the normal bound).
TEST_F(CliRobust, StreamedCleanLogRecordsTheLargestResidualTest) {
  const std::string data =
      puma_data({"--noise-force", "0.05", "--noise-moment", "0.005", "--repeat", "5"});
  const Result r = run({"identify", kPumaUrdf, data, "-o", path("p.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err, "");
  const auto j = nlohmann::json::parse(read_file(path("p.json")));
  EXPECT_EQ(j["outliers"]["method"], "largest residual");
  EXPECT_EQ(j["outliers"]["count"], 0);
  // Two-sided normal tail at 1 % over the 6 N = 900 residuals: erfc(b / sqrt 2) = 0.01 / 900.
  const double b = j["outliers"]["threshold"].get<double>();
  EXPECT_NEAR(std::erfc(b / std::sqrt(2.0)), 0.01 / 900, 1e-12);
}

TEST_F(CliRobust, RobustIdentifyRejectsTheSpoiledLines) {
  const std::string data = spoiled_puma();
  const Result r = run({"identify", kPumaUrdf, data, "-o", path("p.json"), "--robust"});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("rejected 2 of 150 samples"), std::string::npos) << r;
  EXPECT_NE(r.out.find("robust: 2 of 150 samples rejected"), std::string::npos) << r;
  const auto j = nlohmann::json::parse(read_file(path("p.json")));
  EXPECT_EQ(j["outliers"]["method"], "rejected");
  EXPECT_EQ(j["outliers"]["lines"], nlohmann::json::array({8, 41}));
  // The clean data's total mass, within the noise.
  const Result clean =
      run({"identify", kPumaUrdf,
           puma_data({"--noise-force", "0.05", "--noise-moment", "0.005", "--repeat", "5"}), "-o",
           path("clean.json")});
  ASSERT_EQ(clean.code, 0) << clean;
  const auto c = nlohmann::json::parse(read_file(path("clean.json")));
  EXPECT_NEAR(j["total_mass"].get<double>(), c["total_mass"].get<double>(), 2e-3);
}

TEST_F(CliRobust, DriftNeedsItsColumn) {
  const std::string data = puma_data({"--noise-force", "0.05", "--sensor-offset", "1,0,0,0,0,0"});
  expect_input_error(run({"identify", kPumaUrdf, data, "-o", path("p.json"), "--drift", "linear"}),
                     {data, "a linear drift needs a t column", "(--drift linear)"});
  expect_input_error(
      run({"identify", kPumaUrdf, data, "-o", path("p.json"), "--drift", "per-block"}),
      {data, "block column"});
  const Result bad = run({"identify", kPumaUrdf, data, "-o", path("p.json"), "--drift", "cubic"});
  EXPECT_EQ(bad.code, 2) << bad;
  EXPECT_FALSE(std::filesystem::exists(path("p.json")));
}

}  // namespace

// --report on identify, predict and compensate --track when what the report needs is missing: the
// CLI says which piece (Python, numpy, matplotlib, the massid package) and how
// to get it, exits 2, and does so before any work (no params file written).
// The reports themselves are tested with pytest (tests/python).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <string>

#include "cli_support.hpp"

namespace {

using namespace massid_cli_test;

class CliReport : public Cli {
 protected:
  void TearDown() override {
    unsetenv("MASSID_PYTHON");
    Cli::TearDown();
  }
  // An "interpreter" that answers the CLI's probe with `code`.
  std::string fake_python(int code) {
    const std::string p =
        file("python" + std::to_string(code), "#!/bin/sh\nexit " + std::to_string(code) + "\n");
    chmod(p.c_str(), 0755);
    return p;
  }
};

TEST_F(CliReport, MissingPythonIsNamedAndNothingIsWritten) {
  const std::string data = puma_data({"--noise-force", "0.05", "--noise-moment", "0.005"});
  setenv("MASSID_PYTHON", "/nonexistent/python3", 1);
  const Result r = run(
      {"identify", kPumaUrdf, data, "-o", path("params.json"), "--report", path("report.html")});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("massid: error: --report needs Python 3: '/nonexistent/python3' cannot be "
                       "run (No such file or directory)"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.out, "");  // before any work
  EXPECT_FALSE(fs::exists(path("params.json")));
  EXPECT_FALSE(fs::exists(path("report.html")));
  // Without --report the interpreter does not matter.
  EXPECT_EQ(run({"identify", kPumaUrdf, data, "-o", path("params.json")}).code, 0);
}

TEST_F(CliReport, EachMissingPieceIsNamedWithItsPackage) {
  const std::string data = puma_data({"--noise-force", "0.05", "--noise-moment", "0.005"});
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("params.json")}).code, 0);
  const struct {
    int code;
    const char* says;
  } cases[] = {{10, "--report needs numpy, which '"},
               {11, "--report needs matplotlib, which '"},
               {12, "--report needs the massid Python package, which '"}};
  for (const auto& c : cases) {
    setenv("MASSID_PYTHON", fake_python(c.code).c_str(), 1);
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"identify", kPumaUrdf, data, "-o", path("p2.json"), "--report", path("r.html")},
             {"predict", kPumaUrdf, path("params.json"), data, "--report", path("r.html")},
             {"compensate", kPumaUrdf, path("params.json"), "--track", "--report",
              path("r.html")}}) {
      const Result r = run(args, data);
      EXPECT_EQ(r.code, 2) << args[0] << " " << c.code << r;
      EXPECT_NE(r.err.find(c.says), std::string::npos) << r;
      EXPECT_NE(r.err.find("or leave out --report"), std::string::npos) << r;
      EXPECT_EQ(r.out, "") << r;
    }
    EXPECT_FALSE(fs::exists(path("p2.json")));
  }
  setenv("MASSID_PYTHON", fake_python(11).c_str(), 1);
  EXPECT_NE(run({"identify", kPumaUrdf, data, "-o", path("p2.json"), "--report", path("r.html")})
                .err.find("apt-get install python3-matplotlib"),
            std::string::npos);
}

// compensate --track --report: the same checks before any work (not a line
// written: the header would be the first), and --report without --track.
TEST_F(CliReport, CompensateTrackReportChecksPythonFirstAndNeedsTrack) {
  const std::string data = puma_data({"--noise-force", "0.05", "--noise-moment", "0.005"});
  ASSERT_EQ(run({"identify", kPumaUrdf, data, "-o", path("params.json")}).code, 0);
  const std::string log = file("log.csv",
                               "t,joint1,joint2,joint3,gx,gy,gz,fx,fy,fz,mx,my,mz\n"
                               "0,0,0,0,0,0,9.8,0,0,0,0,0,0\n");
  setenv("MASSID_PYTHON", "/nonexistent/python3", 1);
  Result r =
      run({"compensate", kPumaUrdf, path("params.json"), "--track", "--report", path("track.html")},
          log);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("massid: error: --report needs Python 3: '/nonexistent/python3' cannot be "
                       "run (No such file or directory)"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(fs::exists(path("track.html")));
  // Without --report the interpreter does not matter.
  r = run({"compensate", kPumaUrdf, path("params.json"), "--track"}, log);
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("payload_m"), std::string::npos) << r;
  unsetenv("MASSID_PYTHON");
  // A report that could not be written at the end of the stream is refused at its start.
  r = run({"compensate", kPumaUrdf, path("params.json"), "--track", "--report",
           path("no/such/dir/track.html")},
          log);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("/no/such/dir (No such file or directory)"), std::string::npos) << r;
  EXPECT_EQ(r.out, "");
  r = run({"compensate", kPumaUrdf, path("params.json"), "--report", path("track.html")}, log);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("compensate --report draws a tracked log: it goes with --track"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.out, "");
}

}  // namespace

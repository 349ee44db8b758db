// --report on identify and predict when what the report needs is missing: the
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
             {"predict", kPumaUrdf, path("params.json"), data, "--report", path("r.html")}}) {
      const Result r = run(args);
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

}  // namespace

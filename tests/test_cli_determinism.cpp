// Determinism of the CLI: `massid identify` run twice on the same inputs writes
// byte-identical parameter files and reports. The log spans several of the
// streaming reader's 4 MB blocks, so the blocks are reduced on the tool's
// threads (std::thread::hardware_concurrency(); there is no option to set
// their number, and the library test test_numerical_range.cpp compares 1, 2
// and 4 threads bit for bit).
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace massid_cli_test {
namespace {

class CliDeterminism : public Cli {};

// The report without its last line ("wrote <file>"), which names the output.
std::string without_last_line(const std::string& text) {
  const size_t end = text.rfind('\n', text.size() >= 2 ? text.size() - 2 : 0);
  return end == std::string::npos ? std::string() : text.substr(0, end + 1);
}

TEST_F(CliDeterminism, IdentifyTwiceGivesByteIdenticalParams) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  const std::string data = path("log.csv");
  // 60 poses x 1500 noisy samples: 90 000 rows, several blocks.
  const Result sim =
      run({"simulate", urdf, example("ur_like/plan.csv"), "-o", data, "--repeat", "1500",
           "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", "4"});
  ASSERT_EQ(sim.code, 0) << sim;
  ASSERT_GT(fs::file_size(data), 3u * (4u << 20)) << "the log should span several blocks";
  for (const bool offset : {false, true}) {
    SCOPED_TRACE(offset ? "with offsets" : "without offsets");
    std::vector<std::string> reports, params;
    for (const std::string name : {"a.json", "b.json"}) {
      std::vector<std::string> args{"identify", urdf, data, "-o", path(name)};
      if (offset) args.emplace_back("--offset");
      const Result r = run(args);
      ASSERT_EQ(r.code, 0) << r;
      EXPECT_NE(r.out.find("from 90000 samples"), std::string::npos) << r;
      reports.push_back(without_last_line(r.out));
      params.push_back(read_file(path(name)));
    }
    ASSERT_FALSE(params[0].empty());
    EXPECT_EQ(params[0], params[1]);
    EXPECT_EQ(reports[0], reports[1]);
    // And the numbers are the estimate, not an empty or failed report.
    const json j = json::parse(params[0]);
    EXPECT_FALSE(j.empty());
  }
}

}  // namespace
}  // namespace massid_cli_test

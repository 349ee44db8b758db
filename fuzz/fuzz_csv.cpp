// libFuzzer target: the CSV readers. The input is a plan or data file.
//  - read_csv (the whole-file reader) and read_samples against each example
//    robot, as `simulate`, `predict` and `design --evaluate` read files;
//  - identify_csv, the memory-mapped streaming reader of `identify`
//    (csv_stream.cpp), with a tiny block size so that block boundaries fall
//    inside lines, quotes and CRLF pairs, and with the default one.
// With FUZZ_CSV_DIFF=1 in the environment it also checks that both readers
// accept the same files (a finding otherwise).
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace {

using namespace massid;

struct Robot {
  const fuzz::ExampleRobot* example;
  BaseParameters base;
};

const std::vector<Robot>& robots() {
  static const std::vector<Robot> r = [] {
    std::vector<Robot> out;
    for (const auto& e : fuzz::example_robots()) out.push_back({&e, find_base_parameters(e.model)});
    return out;
  }();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::ScratchFile scratch(".csv");
  static const bool diff = [] {
    const char* v = std::getenv("FUZZ_CSV_DIFF");
    return v && std::string(v) == "1";
  }();
  const std::string& path = scratch.write(data, size);

  CsvTable table;
  std::string whole_file_error;
  fuzz::expect_clean("read_csv", [&] {
    try {
      table = read_csv(path);
    } catch (const InputError& e) {
      whole_file_error = e.what();
    }
  });
  for (const Robot& robot : robots()) {
    const Model& model = robot.example->model;
    std::string whole_error = whole_file_error;
    if (whole_file_error.empty()) {
      fuzz::expect_clean("read_samples(Optional)", [&] {
        const Samples s = read_samples(model, table, WrenchColumns::Optional);
        (void)s;
      });
      fuzz::expect_clean("read_samples(Required)", [&] {
        try {
          const Samples s = read_samples(model, table, WrenchColumns::Required);
          (void)s;
        } catch (const InputError& e) {
          whole_error = e.what();
        }
      });
    }
    for (const std::size_t block_bytes : {std::size_t(5), std::size_t(4) << 20}) {
      StreamOptions stream;
      stream.threads = 1;
      stream.block_bytes = block_bytes;
      std::string stream_error;
      fuzz::expect_clean("identify from the streaming reader", [&] {
        try {
          const IdentifyAccumulator acc = accumulate_csv(model, robot.base, path, stream);
          const IdentifySummary s = acc.finish();
          (void)residual_max_csv(model, robot.base, path, s.value, stream);
        } catch (const InputError& e) {
          stream_error = e.what();
        }
      });
      // Both readers must accept or reject the same files (the first error
      // may differ: read_samples reads column by column, the stream row by row).
      if (diff && whole_error.empty() != stream_error.empty()) {
        std::fprintf(stderr,
                     "fuzz: readers disagree on robot %s (block %zu bytes):\n"
                     "  read_csv + read_samples: %s\n  streaming: %s\n",
                     robot.example->name.c_str(), block_bytes,
                     whole_error.empty() ? "accepted" : whole_error.c_str(),
                     stream_error.empty() ? "accepted" : stream_error.c_str());
        std::abort();
      }
    }
  }
  return 0;
}

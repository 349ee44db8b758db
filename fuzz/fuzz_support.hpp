// Shared by the libFuzzer targets: the example robots, a scratch file for the
// readers that take paths, and the rule for what counts as a finding.
//
// A finding is a crash, a sanitizer report, a leak, a timeout, or any exception
// other than massid's own InputError / IdentifiabilityError: bad input must be
// rejected with a message naming the file (and line, column), never with a
// stray std::out_of_range or nlohmann error that the CLI reports as internal.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace massid::fuzz {

// The text of a file of the source tree (examples/...).
inline std::string source_file(const std::string& relative) {
  const std::string path = std::string(MASSID_SOURCE_DIR) + "/" + relative;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "fuzz: cannot read %s\n", path.c_str());
    std::abort();
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The URDFs of examples/ (loaded once; the seeds are made from their files).
struct ExampleRobot {
  std::string name, urdf_text;
  Model model;
};

inline const std::vector<ExampleRobot>& example_robots() {
  static const std::vector<ExampleRobot> robots = [] {
    std::vector<ExampleRobot> out;
    for (const char* name : {"puma260", "ur_like", "branching", "wrist_tool"}) {
      const std::string file = std::string("examples/") + name + "/" + name + ".urdf";
      ExampleRobot r;
      r.name = name;
      r.urdf_text = source_file(file);
      r.model = load_urdf_string(r.urdf_text, "", file);
      out.push_back(std::move(r));
    }
    return out;
  }();
  return robots;
}

// A file in $TMPDIR (else /tmp) rewritten for every input, removed at exit.
class ScratchFile {
 public:
  explicit ScratchFile(const char* suffix) {
    const char* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/massid_fuzz_" + std::to_string(getpid()) +
            suffix;
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  const std::string& write(const uint8_t* data, size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      std::fprintf(stderr, "fuzz: cannot write %s\n", path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string path_;
};

// Runs f; massid's own errors are the expected outcome of bad input, anything
// else aborts (a finding). Returns true when f returned normally.
template <class F>
bool expect_clean(const char* what, F&& f) {
  try {
    f();
    return true;
  } catch (const InputError&) {
  } catch (const IdentifiabilityError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: %s threw an unexpected exception: %s\n", what, e.what());
    std::abort();
  }
  return false;
}

}  // namespace massid::fuzz

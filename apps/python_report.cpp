#include "python_report.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "hints.hpp"
#include "massid/core/errors.hpp"

extern char** environ;

#ifndef MASSID_PYTHON_EXECUTABLE
#define MASSID_PYTHON_EXECUTABLE "python3"
#endif

namespace massid::cli {

namespace {

std::string interpreter() {
  const char* env = std::getenv("MASSID_PYTHON");
  return env && *env ? env : MASSID_PYTHON_EXECUTABLE;
}

// The environment with the build tree's package first on PYTHONPATH.
std::vector<std::string> child_environment() {
  std::vector<std::string> env;
  std::string python_path;
  for (char** e = environ; *e; ++e) {
    if (std::strncmp(*e, "PYTHONPATH=", 11) == 0)
      python_path = *e + 11;
    else
      env.emplace_back(*e);
  }
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto dir = exe.parent_path() / "python";
    if (std::filesystem::exists(dir / "massid" / "__init__.py", ec))
      python_path = python_path.empty() ? dir.string() : dir.string() + ":" + python_path;
  }
  if (!python_path.empty()) env.push_back("PYTHONPATH=" + python_path);
  return env;
}

// Runs the interpreter with args; -1 when it cannot be started (errno kept).
// quiet: its output goes to /dev/null; to_stderr: its stdout goes to our
// stderr (compensate's stdout is the data).
int spawn_python(const std::vector<std::string>& args, bool quiet, bool to_stderr = false) {
  std::vector<std::string> argv_s{interpreter()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_s = child_environment();
  std::vector<char*> envp;
  for (auto& e : env_s) envp.push_back(e.data());
  envp.push_back(nullptr);

  std::cout.flush();  // what the command printed comes before the child's output
  std::cerr.flush();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  } else if (to_stderr) {
    posix_spawn_file_actions_adddup2(&actions, 2, 1);
  }
  pid_t pid = 0;
  const int err = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    errno = err;
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

// Exit codes of the probe: what is missing.
constexpr const char* kProbe =
    "import sys\n"
    "try:\n    import numpy\nexcept ImportError:\n    sys.exit(10)\n"
    "try:\n    import matplotlib\nexcept ImportError:\n    sys.exit(11)\n"
    "try:\n    import massid.report\nexcept ImportError:\n    sys.exit(12)\n";

}  // namespace

void check_report_tools() {
  const std::string py = interpreter();
  const int code = spawn_python({"-c", kProbe}, true);
  const std::string fix = "or leave out --report";
  switch (code) {
    case 0:
      return;
    case -1:
      throw InputError(fmt::format(
          "--report needs Python 3: '{}' cannot be run ({}); install python3, set MASSID_PYTHON "
          "to an interpreter with numpy and matplotlib, {}",
          py, std::strerror(errno), fix));
    case 10:
      throw InputError(fmt::format(
          "--report needs numpy, which '{}' lacks (Debian: apt-get install python3-numpy; or set "
          "MASSID_PYTHON), {}",
          py, fix));
    case 11:
      throw InputError(
          fmt::format("--report needs matplotlib, which '{}' lacks (Debian: apt-get install "
                      "python3-matplotlib; or set MASSID_PYTHON), {}",
                      py, fix));
    case 12:
      throw InputError(fmt::format(
          "--report needs the massid Python package, which '{}' cannot import (build with "
          "-DMASSID_PYTHON=ON and run this massid from the build tree, or cmake --install; or "
          "set PYTHONPATH), {}",
          py, fix));
    default:
      throw InputError(
          fmt::format("--report: '{}' failed to start (exit code {}), {}", py, code, fix));
  }
}

int run_report(const std::vector<std::string>& args, bool to_stderr) {
  std::vector<std::string> full{"-m", "massid.report"};
  full.insert(full.end(), args.begin(), args.end());
  const int code = spawn_python(full, false, to_stderr);
  if (code == -1)
    throw InputError(
        fmt::format("--report: '{}' cannot be run ({})", interpreter(), std::strerror(errno)));
  return code == 2 || code == 3 ? code : (code == 0 ? 0 : 1);
}

namespace {

// A new empty temporary file named after pattern (ending in XXXXXX); its open
// descriptor.
int temporary_file(std::string& path, const char* pattern) {
  path = (std::filesystem::temp_directory_path() / pattern).string();
  const int fd = mkstemp(path.data());
  if (fd < 0)
    throw InputError(fmt::format("--report: cannot create a temporary file {} ({})", path,
                                 std::strerror(errno)));
  return fd;
}

}  // namespace

int run_identify_report(const Identification& ident, const std::string& report) {
  std::string record;
  close(temporary_file(record, "massid-identification-XXXXXX"));
  struct Remove {
    const std::string& path;
    ~Remove() { std::remove(path.c_str()); }
  } remove{record};
  write_identification(record, ident, spell);  // as the command printed them
  return run_report({"draw-identify", record, "-o", report});
}

TrackReport::TrackReport(std::string report, std::string source, std::string time_column)
    : report_(std::move(report)), source_(std::move(source)), time_(std::move(time_column)) {
  const int fd = temporary_file(spool_, "massid-track-XXXXXX");
  file_ = fdopen(fd, "w");
  if (!file_) {
    const int e = errno;
    close(fd);
    std::remove(spool_.c_str());
    throw InputError(fmt::format("--report: cannot open the spool {} ({})", spool_, strerror(e)));
  }
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

TrackReport::~TrackReport() {
  if (file_) std::fclose(file_);
  std::remove(spool_.c_str());
}

void TrackReport::write(std::string_view text) {
  if (!failed_ && std::fwrite(text.data(), 1, text.size(), file_) != text.size()) {
    failed_ = true;
    error_ = errno;
  }
}

int TrackReport::render() {
  if (std::fflush(file_) != 0 && !failed_) failed_ = true, error_ = errno;
  std::fclose(file_);
  file_ = nullptr;
  if (failed_)
    throw InputError(fmt::format(
        "--report: writing the tracked rows to the spool {} failed ({}): no report written", spool_,
        std::strerror(error_)));
  return run_report({"track", spool_, "-o", report_, "--source", source_, "--time", time_}, true);
}

}  // namespace massid::cli

// Shared helpers of the CLI tests (test_cli.cpp, test_cli_design.cpp): run the
// massid binary as a user would, capture its exit code and output, read the CSV
// files it writes.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

extern char** environ;

namespace massid_cli_test {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline const std::string kExe = MASSID_EXE;
inline const std::string kSource = MASSID_SOURCE_DIR;

inline std::string example(const std::string& rel) { return kSource + "/examples/" + rel; }
inline const std::string kPumaUrdf = example("puma260/puma260.urdf");
inline const std::string kPumaPlan = example("puma260/plan.csv");
inline const std::string kUrUrdf = example("ur_like/ur_like.urdf");

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

inline int count_lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n';
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

// A UDP socket sending datagrams to 127.0.0.1:port (compensate --udp).
class LoopbackSender {
 public:
  explicit LoopbackSender(int port) : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    to_.sin_family = AF_INET;
    to_.sin_port = htons(static_cast<uint16_t>(port));
    to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  ~LoopbackSender() {
    if (fd_ >= 0) close(fd_);
  }
  LoopbackSender(const LoopbackSender&) = delete;
  LoopbackSender& operator=(const LoopbackSender&) = delete;
  int fd() const { return fd_; }
  // One datagram; true when it was sent whole.
  bool send(std::string_view text) const {
    return sendto(fd_, text.data(), text.size(), 0, reinterpret_cast<const sockaddr*>(&to_),
                  sizeof to_) == static_cast<ssize_t>(text.size());
  }

 private:
  int fd_ = -1;
  sockaddr_in to_{};
};

struct Result {
  int code = -1;
  std::string out, err;
};

inline std::ostream& operator<<(std::ostream& os, const Result& r) {
  return os << "exit " << r.code << "\n--- stdout ---\n" << r.out << "--- stderr ---\n" << r.err;
}

// A CSV as the tool writes it: cells with a comma or quote are double-quoted.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
  double num(size_t r, const std::string& name) const {
    const int c = col(name);
    EXPECT_GE(c, 0) << "no column " << name;
    return c < 0 ? NAN : std::stod(rows[r][c]);
  }
};

inline std::vector<std::string> split_line(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      f.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      f.emplace_back();
    } else {
      f.back() += c;
    }
  }
  return f;
}

inline Table read_table(const std::string& path) {
  Table t;
  std::istringstream in(read_file(path));
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (t.header.empty())
      t.header = split_line(line);
    else
      t.rows.push_back(split_line(line));
  }
  return t;
}

// The non-comment lines of a plan, split into cells.
inline Table read_plan(const std::string& path) { return read_table(path); }

// The table without the columns `drop` says yes to.
template <class Drop>
inline Table without_columns(const Table& t, Drop drop) {
  Table p;
  std::vector<int> keep;
  for (size_t c = 0; c < t.header.size(); ++c)
    if (!drop(t.header[c])) {
      keep.push_back(static_cast<int>(c));
      p.header.push_back(t.header[c]);
    }
  for (const auto& row : t.rows) {
    std::vector<std::string> r;
    for (int c : keep) r.push_back(row[c]);
    p.rows.push_back(r);
  }
  return p;
}

inline std::string join(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + cells[i];
  return s;
}

inline std::string to_csv(const Table& t) {
  std::string s = join(t.header) + "\n";
  for (const auto& r : t.rows) s += join(r) + "\n";
  return s;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "massid_cli_XXXXXX").string();
    ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  std::string file(const std::string& name, const std::string& text) const {
    write_file(path(name), text);
    return path(name);
  }
  // A copy of the CSV `in` with every row passed through `edit`.
  std::string edited(const std::string& in, const std::string& name,
                     const std::function<void(const Table&, std::vector<std::string>&)>& edit) {
    Table t = read_table(in);
    for (auto& row : t.rows) edit(t, row);
    return file(name, to_csv(t));
  }

  // Runs massid with args; stdout and stderr go to files of the temp dir,
  // stdin comes from the file `input`.
  Result run(const std::vector<std::string>& args, const std::string& input = "/dev/null") {
    const std::string out = path(".stdout"), err = path(".stderr");
    std::vector<std::string> argv_s{kExe};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, input.c_str(), O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    Result r;
    const int rc = posix_spawn(&pid, kExe.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
      ADD_FAILURE() << "cannot run " << kExe;
      return r;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = read_file(out);
    r.err = read_file(err);
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  // Files in the temp dir (hidden capture files excluded).
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n[0] != '.') names.push_back(n);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  // Simulated PUMA data from the example plan.
  std::string puma_data(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"simulate", kPumaUrdf, kPumaPlan, "-o", path("puma_data.csv")};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return path("puma_data.csv");
  }

  std::string dir_;
};

// Exit 2, nothing on stdout, one line on stderr containing every piece.
inline void expect_input_error(const Result& r, const std::vector<std::string>& pieces) {
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(r.out, "") << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_EQ(r.err.rfind("massid: error: ", 0), 0u) << r;
  for (const auto& p : pieces)
    EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' in\n" << r;
}

}  // namespace massid_cli_test

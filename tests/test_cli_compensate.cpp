// `massid compensate` as a robot controller runs it: a producer process
// writing samples into a pipe (or loopback UDP datagrams) and reading each
// compensated line back before it sends the next. The compensated wrench is
// checked against the URDF's own wrench (simulate, noise-free) and the
// offsets that were put into the data, not against massid's predictor.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>

#include <chrono>
#include <optional>
#include <random>
#include <regex>
#include <thread>

#include "cli_support.hpp"
#include "latency_histogram.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/live/identified_model.hpp"

namespace massid_cli_test {
namespace {

using Clock = std::chrono::steady_clock;

// A running `massid ARGS...` with pipes to its stdin, stdout and stderr.
class Live {
 public:
  explicit Live(const std::vector<std::string>& args) {
    int in[2], out[2], err[2];
    EXPECT_EQ(pipe(in), 0);
    EXPECT_EQ(pipe(out), 0);
    EXPECT_EQ(pipe(err), 0);
    std::vector<std::string> argv_s{kExe};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    for (int fd : {in[0], in[1], out[0], out[1], err[0], err[1]})
      posix_spawn_file_actions_addclose(&fa, fd);
    EXPECT_EQ(posix_spawn(&pid_, kExe.c_str(), &fa, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&fa);
    close(in[0]);
    close(out[1]);
    close(err[1]);
    in_ = in[1];
    fcntl(in_, F_SETFL, O_NONBLOCK);  // send() interleaves writes and reads
    out_ = out[0];
    err_ = err[0];
    signal(SIGPIPE, SIG_IGN);
  }
  ~Live() {
    close_input();
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(out_);
    close(err_);
  }
  Live(const Live&) = delete;
  Live& operator=(const Live&) = delete;

  // Writes text to the command's stdin, reading its stdout and stderr
  // meanwhile (a large input would otherwise fill both pipes and stall);
  // stops where the command has closed its input.
  void send(const std::string& text) {
    const char* p = text.data();
    size_t n = text.size();
    while (n > 0) {
      pollfd fds[3] = {{in_, POLLOUT, 0}, {out_, POLLIN, 0}, {err_, POLLIN, 0}};
      ASSERT_GT(poll(fds, 3, 10000), 0) << "the command neither reads nor writes for 10 s";
      if (fds[1].revents & POLLIN) read_some(out_, out_buf_, 0);
      if (fds[2].revents & POLLIN) read_some(err_, err_buf_, 0);
      if (!(fds[0].revents & (POLLOUT | POLLERR))) continue;
      const ssize_t w = write(in_, p, n);
      if (w < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (w <= 0) return;  // the command closed its input (it exited): what it wrote tells
      p += w;
      n -= static_cast<size_t>(w);
    }
  }
  void close_input() {
    if (in_ >= 0) close(in_);
    in_ = -1;
  }
  // The next line of stdout (without '\n'), or nullopt after timeout_ms.
  std::optional<std::string> line(int timeout_ms = 10000) {
    return take(out_, out_buf_, timeout_ms);
  }
  // The next line of stderr.
  std::optional<std::string> err_line(int timeout_ms = 10000) {
    return take(err_, err_buf_, timeout_ms);
  }
  // Waits for the exit (killing the process after timeout_ms); the exit code,
  // and the rest of stdout and stderr in `out` and `err`.
  int wait(int timeout_ms = 20000) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      drain();
      if (Clock::now() > deadline) {
        ADD_FAILURE() << "massid compensate did not end within " << timeout_ms << " ms";
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    exited_ = true;
    drain();
    out = out_buf_;
    err = err_buf_;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  void signal_stop(int sig) { kill(pid_, sig); }
  std::string out, err;

 private:
  static bool read_some(int fd, std::string& buf, int timeout_ms) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) return false;
    char chunk[65536];
    const ssize_t n = read(fd, chunk, sizeof chunk);
    if (n <= 0) return false;
    buf.append(chunk, static_cast<size_t>(n));
    return true;
  }
  static std::optional<std::string> take(int fd, std::string& buf, int timeout_ms) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
    while (buf.find('\n') == std::string::npos) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (left.count() <= 0 || !read_some(fd, buf, static_cast<int>(left.count())))
        return std::nullopt;
    }
    const size_t nl = buf.find('\n');
    std::string line = buf.substr(0, nl);
    buf.erase(0, nl + 1);
    return line;
  }
  void drain() {
    while (read_some(out_, out_buf_, 0)) {
    }
    while (read_some(err_, err_buf_, 0)) {
    }
  }
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1, err_ = -1;
  bool exited_ = false;
  std::string out_buf_, err_buf_;
};

// The lines of a CSV file that are neither blank nor comments.
std::vector<std::string> csv_lines(const std::string& path) {
  std::vector<std::string> lines;
  std::istringstream in(read_file(path));
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  return lines;
}

// The figures of compensate --stats: median, 99.9th percentile and max, us.
struct Stats {
  long samples = -1, skipped = -1;
  double median = -1, p999 = -1, max = -1;
};
Stats parse_stats(const std::string& err) {
  static const std::regex re(
      R"(compensate: (\d+) samples, (\d+) lines skipped; added latency \(parse, predict, format\) )"
      R"(median ([0-9.]+) us, 99\.9th percentile ([0-9.]+) us, max ([0-9.]+) us)");
  std::smatch m;
  Stats s;
  if (std::regex_search(err, m, re)) {
    s.samples = std::stol(m[1]);
    s.skipped = std::stol(m[2]);
    s.median = std::stod(m[3]);
    s.p999 = std::stod(m[4]);
    s.max = std::stod(m[5]);
  }
  return s;
}

// --stats' histogram against a direct sort: each percentile within the
// bucket resolution (exact below 4096 ns, 1/256 relative above), never below
// the true order statistic, and the max exact.
TEST(LatencyHistogram, PercentilesMatchTheSortedRecords) {
  std::mt19937_64 rng(5);
  std::lognormal_distribution<double> d(7.0, 1.5);  // median ~1.1 us, a long tail
  massid::LatencyHistogram h;
  std::vector<std::int64_t> v;
  for (int i = 0; i < 100000; ++i) {
    v.push_back(static_cast<std::int64_t>(d(rng)));
    h.record(v.back());
  }
  std::sort(v.begin(), v.end());
  EXPECT_EQ(h.count(), 100000);
  EXPECT_EQ(h.max(), v.back());
  for (const double p : {0.001, 0.5, 0.9, 0.999, 1.0}) {
    const double exact = static_cast<double>(v[static_cast<size_t>(std::ceil(p * 1e5)) - 1]);
    EXPECT_GE(h.percentile(p), exact) << p;
    EXPECT_LE(h.percentile(p), exact < 4096 ? exact : exact * (1 + 1.0 / 256)) << p;
  }
  EXPECT_EQ(massid::LatencyHistogram().percentile(0.5), 0.0);
}

const char* const kWrench[] = {"fx", "fy", "fz", "mx", "my", "mz"};
const std::string kHoldout = example("puma260/holdout.csv");

class CliCompensate : public Cli {
 protected:
  // PUMA params identified with offsets from noise-free data at the 200
  // poses of the holdout (tilted in every direction: the base parameters and
  // offsets exact), and a stream at the same poses with noise and the same
  // offsets; truth.csv the URDF's own wrench there (noise-free, no offset).
  void SetUp() override {
    Cli::SetUp();
    Result r =
        run({"simulate", kPumaUrdf, kHoldout, "-o", path("fit.csv"), "--sensor-offset", kOffset});
    ASSERT_EQ(r.code, 0) << r;
    r = run({"identify", kPumaUrdf, path("fit.csv"), "--offset", "--sigma-force", "0.05",
             "--sigma-moment", "0.005", "-o", path("params.json")});
    ASSERT_EQ(r.code, 0) << r;
    r = run({"simulate", kPumaUrdf, kHoldout, "-o", path("stream.csv"), "--sensor-offset", kOffset,
             "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", "3"});
    ASSERT_EQ(r.code, 0) << r;
    r = run({"simulate", kPumaUrdf, kHoldout, "-o", path("truth.csv")});
    ASSERT_EQ(r.code, 0) << r;
  }
  // measured - URDF wrench - offset for row i of `stream` and `truth`.
  static double expected(const Table& stream, const Table& truth, size_t i, int k) {
    static const double offset[6] = {1.5, -2, 0.5, 0.1, -0.2, 0.05};
    return stream.num(i, kWrench[k]) - truth.num(i, kWrench[k]) - offset[k];
  }
  static void expect_compensated(const Table& out, const Table& stream, const Table& truth,
                                 size_t out_row, size_t row) {
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(out.num(out_row, std::string(kWrench[k]) + "_comp"),
                  expected(stream, truth, row, k), 1e-7)
          << kWrench[k] << " row " << row;
  }
  std::vector<std::string> args(std::vector<std::string> extra = {}) {
    std::vector<std::string> a{"compensate", kPumaUrdf, path("params.json")};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  static constexpr const char* kOffset = "1.5,-2,0.5,0.1,-0.2,0.05";
};

// A whole file through a pipe: every row, the input columns kept verbatim,
// fx_comp..mz_comp the measured wrench minus the URDF's minus the offsets;
// the same as predict's _comp; exit 0 at the end of input.
TEST_F(CliCompensate, PipeEqualsMeasuredMinusUrdfWrenchAndPredict) {
  Live live(args({"--stats"}));
  live.send(read_file(path("stream.csv")));
  live.close_input();
  ASSERT_EQ(live.wait(), 0) << live.err;
  write_file(path("out.csv"), live.out);
  const Table out = read_table(path("out.csv"));
  const Table stream = read_table(path("stream.csv")), truth = read_table(path("truth.csv"));
  ASSERT_EQ(out.rows.size(), 200u);
  std::vector<std::string> header = stream.header;
  for (const char* w : kWrench) header.push_back(std::string(w) + "_comp");
  EXPECT_EQ(out.header, header);
  const std::vector<std::string> in_lines = csv_lines(path("stream.csv"));
  const std::vector<std::string> out_lines = csv_lines(path("out.csv"));
  for (size_t i = 0; i < 200; ++i) {
    EXPECT_EQ(out_lines[i + 1].rfind(in_lines[i + 1] + ",", 0), 0u) << i;
    expect_compensated(out, stream, truth, i, i);
  }
  // predict's _comp columns: the same numbers.
  const Result r =
      run({"predict", kPumaUrdf, path("params.json"), path("stream.csv"), "-o", path("pred.csv")});
  ASSERT_EQ(r.code, 0) << r;
  const Table pred = read_table(path("pred.csv"));
  for (size_t i = 0; i < 200; ++i)
    for (const char* w : kWrench) {
      const std::string c = std::string(w) + "_comp";
      EXPECT_EQ(out.rows[i][out.col(c)], pred.rows[i][pred.col(c)]) << c << " row " << i;
    }
  const Stats s = parse_stats(live.err);
  EXPECT_EQ(s.samples, 200) << live.err;
  EXPECT_EQ(s.skipped, 0);
  EXPECT_GT(s.median, 0.0) << live.err;
  EXPECT_LE(s.median, s.p999) << live.err;
  EXPECT_LE(s.p999, s.max) << live.err;
}

// A producer that sends bursts of lines with pauses between them and reads
// every output line back before it goes on: each line is written (flushed)
// as soon as its sample arrives, not when a buffer fills or input ends.
TEST_F(CliCompensate, EachLineComesBackBeforeTheNextIsSent) {
  const std::vector<std::string> lines = csv_lines(path("stream.csv"));
  const Table stream = read_table(path("stream.csv")), truth = read_table(path("truth.csv"));
  Live live(args());
  live.send(lines[0] + "\n");
  const std::optional<std::string> header = live.line();
  ASSERT_TRUE(header) << "no header line within 10 s";
  EXPECT_EQ(*header, lines[0] + ",fx_comp,fy_comp,fz_comp,mx_comp,my_comp,mz_comp");
  size_t row = 0;
  std::string got;
  for (int burst = 0; burst < 5; ++burst) {
    // A burst: 20 lines written at once, then their 20 outputs.
    std::string text;
    for (int k = 0; k < 20; ++k) text += lines[1 + row + k] + "\n";
    live.send(text);
    for (int k = 0; k < 20; ++k) {
      const std::optional<std::string> out = live.line();
      ASSERT_TRUE(out) << "no output for row " << row + k << " within 10 s";
      got += *out + "\n";
    }
    row += 20;
    // Then one line at a time, each answered before the next, with pauses.
    for (int k = 0; k < 5; ++k, ++row) {
      live.send(lines[1 + row] + "\n");
      const std::optional<std::string> out = live.line();
      ASSERT_TRUE(out) << "no output for row " << row << " within 10 s";
      got += *out + "\n";
      std::this_thread::sleep_for(std::chrono::milliseconds(k == 0 ? 50 : 2));
    }
  }
  live.close_input();
  EXPECT_EQ(live.wait(), 0) << live.err;
  EXPECT_EQ(live.err, "");
  write_file(path("out.csv"), *header + "\n" + got);
  const Table out = read_table(path("out.csv"));
  ASSERT_EQ(out.rows.size(), row);
  for (size_t i = 0; i < row; ++i) expect_compensated(out, stream, truth, i, i);
}

// Malformed lines are named on stderr with their line numbers and skipped;
// the good lines around them come through; the stream ends with exit 0.
TEST_F(CliCompensate, MalformedLinesAreReportedAndSkipped) {
  const std::vector<std::string> lines = csv_lines(path("stream.csv"));
  const Table stream = read_table(path("stream.csv")), truth = read_table(path("truth.csv"));
  // Row 0 of the stream with one cell replaced.
  const auto with_cell = [&](const std::string& column, const std::string& value) {
    std::vector<std::string> cells = stream.rows[0];
    cells[stream.col(column)] = value;
    return join(cells);
  };
  std::vector<std::string> row0 = stream.rows[0];
  row0.pop_back();
  const std::string input = lines[0] + "\n" +                    // line 1
                            lines[1] + "\n" +                    // 2: good
                            join(row0) + "\n" +                  // 3: a field short
                            lines[2] + "\n" +                    // 4: good
                            with_cell("fx", "abc") + "\n" +      // 5: text
                            with_cell("joint2", "nan") + "\n" +  // 6: nan
                            with_cell("gz", "") + "\n" +         // 7: empty cell
                            "\n" +                               // 8: empty line
                            "# a comment\n" +                    // 9: skipped silently
                            lines[3] + "\n" +                    // 10: good
                            lines[4];                            // 11: good, no line end
  Live live(args({"--stats"}));
  live.send(input);
  live.close_input();
  ASSERT_EQ(live.wait(), 0) << live.err;
  write_file(path("out.csv"), live.out);
  const Table out = read_table(path("out.csv"));
  ASSERT_EQ(out.rows.size(), 4u) << live.out;
  for (size_t i = 0; i < 4; ++i) expect_compensated(out, stream, truth, i, i);
  std::vector<std::string> err;
  std::istringstream es(live.err);
  for (std::string l; std::getline(es, l);)
    if (l.find("latency") == std::string::npos) err.push_back(l);
  ASSERT_EQ(err.size(), 5u) << live.err;
  EXPECT_NE(err[0].find("stdin:3:"), std::string::npos) << err[0];
  EXPECT_NE(err[0].find("row has 13 fields, the header has 14"), std::string::npos) << err[0];
  EXPECT_NE(err[1].find("stdin:5:"), std::string::npos) << err[1];
  EXPECT_NE(err[1].find("column 'fx': 'abc' is not a number"), std::string::npos) << err[1];
  EXPECT_NE(err[2].find("stdin:6:"), std::string::npos) << err[2];
  EXPECT_NE(err[2].find("column 'joint2': 'nan' is not a finite number"), std::string::npos)
      << err[2];
  EXPECT_NE(err[3].find("stdin:7:"), std::string::npos) << err[3];
  EXPECT_NE(err[3].find("column 'gz': empty cell"), std::string::npos) << err[3];
  EXPECT_NE(err[4].find("stdin:8: empty line"), std::string::npos) << err[4];
  for (const std::string& e : err) EXPECT_EQ(e.rfind("massid: stdin:", 0), 0u) << e;
  const Stats s = parse_stats(live.err);
  EXPECT_EQ(s.samples, 4);
  EXPECT_EQ(s.skipped, 5);
}

// Loopback UDP: the command says its port (bound with --udp 0), takes the
// header and one sample per datagram, skips a malformed one with its
// datagram number, answers with --reply, and ends at an empty datagram.
TEST_F(CliCompensate, UdpLoopbackWithMalformedDatagramsAndReplies) {
  const std::vector<std::string> lines = csv_lines(path("stream.csv"));
  const Table stream = read_table(path("stream.csv")), truth = read_table(path("truth.csv"));
  Live live(args({"--udp", "0", "--reply", "--stats"}));
  const std::optional<std::string> hello = live.err_line();
  ASSERT_TRUE(hello) << "no port within 10 s";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(*hello, m, std::regex(R"(udp 127\.0\.0\.1:(\d+))"))) << *hello;
  const int port = std::stoi(m[1]);
  ASSERT_GT(port, 0);

  const LoopbackSender sender(port);
  ASSERT_GE(sender.fd(), 0);
  const auto send_line = [&](const std::string& text) { ASSERT_TRUE(sender.send(text)); };
  const auto reply = [&]() -> std::optional<std::string> {
    pollfd p{sender.fd(), POLLIN, 0};
    if (poll(&p, 1, 10000) <= 0) return std::nullopt;
    char buf[65536];
    const ssize_t n = recv(sender.fd(), buf, sizeof buf, 0);
    return n > 0 ? std::optional<std::string>(std::string(buf, static_cast<size_t>(n)))
                 : std::nullopt;
  };
  send_line(lines[0] + "\n");  // datagram 1: the header
  const std::optional<std::string> header = live.line();
  ASSERT_TRUE(header) << "no header within 10 s";
  std::string got = *header + "\n";
  int sent = 0;
  for (int i = 1; i <= 60; ++i) {
    if (i == 30) {
      send_line("1,2,three");  // datagram 31: malformed
      const std::optional<std::string> e = live.err_line();
      ASSERT_TRUE(e) << "no message for the malformed datagram";
      EXPECT_NE(e->find("udp:31:"), std::string::npos) << *e;
      EXPECT_NE(e->find("row has 3 fields"), std::string::npos) << *e;
    }
    send_line(lines[i] + (i % 2 ? "\n" : ""));  // with and without a line end
    ++sent;
    const std::optional<std::string> out = live.line();
    ASSERT_TRUE(out) << "no output for datagram " << i << " within 10 s";
    const std::optional<std::string> back = reply();
    ASSERT_TRUE(back) << "no reply for datagram " << i;
    EXPECT_EQ(*back, *out + "\n");
    got += *out + "\n";
  }
  // A burst of 40 datagrams, then their outputs.
  for (int i = 61; i <= 100; ++i) send_line(lines[i]);
  for (int i = 61; i <= 100; ++i) {
    const std::optional<std::string> out = live.line();
    ASSERT_TRUE(out) << "no output for datagram " << i << " within 10 s";
    got += *out + "\n";
    ++sent;
  }
  send_line("");  // the end
  EXPECT_EQ(live.wait(), 0) << live.err;
  write_file(path("out.csv"), got);
  const Table out = read_table(path("out.csv"));
  ASSERT_EQ(out.rows.size(), 100u);
  for (size_t i = 0; i < 100; ++i) expect_compensated(out, stream, truth, i, i);
  const Stats s = parse_stats(live.err);
  EXPECT_EQ(s.samples, 100) << live.err;
  EXPECT_EQ(s.skipped, 1);
  EXPECT_GT(s.median, 0.0);
  EXPECT_LE(s.median, s.p999);
  EXPECT_LE(s.p999, s.max);
}

// SIGTERM ends a UDP stream cleanly, with the statistics; so does "end".
TEST_F(CliCompensate, UdpEndsAtEndLineAndAtSigterm) {
  const std::vector<std::string> lines = csv_lines(path("stream.csv"));
  for (const bool by_signal : {false, true}) {
    Live live(args({"--udp", "0", "--stats"}));
    const std::optional<std::string> hello = live.err_line();
    ASSERT_TRUE(hello);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(*hello, m, std::regex(R"(:(\d+)$)"))) << *hello;
    const LoopbackSender sender(std::stoi(m[1]));
    for (int i = 0; i <= 3; ++i) {
      sender.send(lines[i]);
      ASSERT_TRUE(live.line()) << i;
    }
    if (by_signal)
      live.signal_stop(SIGTERM);
    else
      sender.send("end\n");
    EXPECT_EQ(live.wait(), 0) << live.err;
    EXPECT_EQ(parse_stats(live.err).samples, 3) << live.err;
  }
}

// The stream's header is checked before any sample: a missing joint or
// wrench column, half a group, no gravity at all, a column compensate would
// write: exit 2 naming the column, nothing on stdout.
TEST_F(CliCompensate, BadHeaderIsExit2NamingTheColumn) {
  const std::vector<std::string> lines = csv_lines(path("stream.csv"));
  const auto run_header = [&](const std::string& header) {
    Live live(args());
    live.send(header + "\n" + lines[1] + "\n");
    live.close_input();
    const int code = live.wait();
    EXPECT_EQ(code, 2) << header << "\n" << live.err;
    EXPECT_EQ(live.out, "") << header;
    EXPECT_EQ(count_lines(live.err), 1) << live.err;
    return live.err;
  };
  std::string e = run_header("joint1,joint3,gx,gy,gz,tilt_x_deg,tilt_y_deg,fx,fy,fz,mx,my,mz");
  EXPECT_NE(e.find("stdin:1: no column for joint 'joint2'"), std::string::npos) << e;
  e = run_header("joint1,joint2,joint3,gx,gy,gz,tilt_x_deg,tilt_y_deg,fx,fy,fz,mx,my");
  EXPECT_NE(e.find("column(s) mz missing"), std::string::npos) << e;
  e = run_header("joint1,joint2,joint3,gx,gz,fx,fy,fz,mx,my,mz");
  EXPECT_NE(e.find("column(s) gy missing"), std::string::npos) << e;
  e = run_header("joint1,joint2,joint3,fx,fy,fz,mx,my,mz");
  EXPECT_NE(e.find("no gravity: add columns gx,gy,gz"), std::string::npos) << e;
  e = run_header("joint1,joint2,joint3,tilt_x_deg,fx,fy,fz,mx,my,mz");
  EXPECT_NE(e.find("column(s) tilt_y_deg missing"), std::string::npos) << e;
  e = run_header("joint1,joint2,joint3,gx,gy,gz,fx,fy,fz,mx,my,mz,fz_comp");
  EXPECT_NE(e.find("column 'fz_comp' is already in the header"), std::string::npos) << e;
  // Comment lines before the header count: the header is line 3.
  e = run_header("# logged by the controller\n\njoint1,joint3,gx,gy,gz,fx,fy,fz,mx,my,mz");
  EXPECT_NE(e.find("stdin:3: no column for joint 'joint2'"), std::string::npos) << e;
}

// Gravity from the platform's tilt (tilt_x_deg, tilt_y_deg, as the plans
// have them) turning the level gravity: the same compensation as from
// gx,gy,gz. The holdout's level gravity is +z (its tilts are of a platform
// hanging the PUMA: --gravity 0,0,9.80665).
TEST_F(CliCompensate, GravityFromTiltColumns) {
  const Table stream = read_table(path("stream.csv")), truth = read_table(path("truth.csv"));
  const Table tilts = without_columns(
      stream, [](const std::string& c) { return c == "gx" || c == "gy" || c == "gz"; });
  Live live(args({"--gravity", "0,0,9.80665"}));
  live.send(to_csv(tilts));
  live.close_input();
  ASSERT_EQ(live.wait(), 0) << live.err;
  write_file(path("out.csv"), live.out);
  const Table out = read_table(path("out.csv"));
  ASSERT_EQ(out.rows.size(), 200u);
  for (size_t i = 0; i < 200; ++i) expect_compensated(out, stream, truth, i, i);
}

// A dynamic params file (identify --dynamic) compensates the full wrench,
// weight and motion, from JOINT_vel and JOINT_acc: on another trajectory the
// URDF's simulated wrench with the same offsets compensates to zero. Without
// the _vel/_acc columns: exit 2 naming them.
TEST_F(Cli, CompensateInMotionWithADynamicFit) {
  const std::string ur = example("ur_like/ur_like.urdf");
  const std::string offset = "1,2,3,0.1,0.2,0.3";
  const auto log = [&](const std::string& name, const std::string& seed, const std::string& s) {
    Result r = run({"design", ur, "--dynamic", "-o", path(name + "_traj.csv"), "--duration", s,
                    "--rate", "200", "--seed", seed, "--evaluations", "300"});
    EXPECT_EQ(r.code, 0) << r;
    r = run({"simulate", ur, path(name + "_traj.csv"), "-o", path(name + ".csv"), "--dynamic",
             "--sensor-offset", offset});
    EXPECT_EQ(r.code, 0) << r;
    return path(name + ".csv");
  };
  Result r = run({"identify", ur, log("fit", "1", "10"), "--dynamic", "--offset", "--sigma-force",
                  "0.05", "--sigma-moment", "0.005", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  const std::string other = log("other", "7", "4");
  Live live({"compensate", ur, path("params.json"), "--stats"});
  live.send(read_file(other));
  live.close_input();
  ASSERT_EQ(live.wait(), 0) << live.err;
  write_file(path("out.csv"), live.out);
  const Table out = read_table(path("out.csv")), in = read_table(other);
  ASSERT_EQ(out.rows.size(), in.rows.size());
  double largest_motion = 0.0;  // how far the wrench is from the static weight: the test's reach
  for (size_t i = 0; i < out.rows.size(); ++i) {
    largest_motion = std::max(largest_motion, std::abs(in.num(i, "fx") - in.num(0, "fx")));
    for (const char* w : kWrench)
      EXPECT_NEAR(out.num(i, std::string(w) + "_comp"), 0.0, 1e-6) << w << " row " << i;
  }
  EXPECT_GT(largest_motion, 1.0);
  EXPECT_EQ(parse_stats(live.err).samples, static_cast<long>(in.rows.size())) << live.err;

  const Table positions = without_columns(in, [](const std::string& c) {
    return c.size() > 4 && (c.ends_with("_vel") || c.ends_with("_acc"));
  });
  Live bad({"compensate", ur, path("params.json")});
  bad.send(to_csv(positions));
  bad.close_input();
  EXPECT_EQ(bad.wait(), 2);
  EXPECT_EQ(bad.out, "");
  EXPECT_NE(bad.err.find("is a dynamic fit"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("shoulder_pan_joint_vel,shoulder_pan_joint_acc"), std::string::npos)
      << bad.err;
  // A tool on a wrist sensor: gravity and the sensor frame's motion from the
  // arm's joints above it (no gx,gy,gz), as predict does; identified on one
  // trajectory, compensated to zero on the other.
  const auto wrist_log = [&](const std::string& traj, const std::string& name) {
    const Table arm = without_columns(read_table(path(traj)), [](const std::string& c) {
      return c == "gx" || c == "gy" || c == "gz";
    });
    write_file(path("arm_" + name), to_csv(arm));
    const Result s =
        run({"simulate", ur, path("arm_" + name), "-o", path(name), "--dynamic", "--sensor",
             "wrist_3_link", "--sensor-offset", "0.1,0.2,0.3,0.01,0.02,0.03"});
    EXPECT_EQ(s.code, 0) << s;
    return arm.rows.size();
  };
  wrist_log("fit_traj.csv", "wrist.csv");
  const size_t rows = wrist_log("other_traj.csv", "wrist_other.csv");
  r = run({"identify", ur, path("wrist.csv"), "--dynamic", "--sensor", "wrist_3_link", "--offset",
           "--sigma-force", "0.01", "--sigma-moment", "0.001", "-o", path("wrist.json")});
  ASSERT_EQ(r.code, 0) << r;
  Live wrist({"compensate", ur, path("wrist.json")});
  wrist.send(read_file(path("wrist_other.csv")));
  wrist.close_input();
  ASSERT_EQ(wrist.wait(), 0) << wrist.err;
  write_file(path("wrist_out.csv"), wrist.out);
  const Table wout = read_table(path("wrist_out.csv"));
  ASSERT_EQ(wout.rows.size(), rows);
  for (size_t i = 0; i < wout.rows.size(); ++i)
    for (const char* w : kWrench)
      EXPECT_NEAR(wout.num(i, std::string(w) + "_comp"), 0.0, 1e-6) << w << " row " << i;
}

// One log with an identified offset through every door of the library's
// identified model: `predict -o` (fx_comp..), `compensate` on stdin, and the
// library's IdentifiedModel (what Python's Predictor and the C interface wrap:
// tests/python/test_ctypes.py checks those two against the same figures):
// the same compensated wrench to the bit, static and in motion. The CLI
// writes shortest round-trip numbers: parsed back they are the doubles.
TEST_F(Cli, EveryDoorGivesTheSameCompensatedWrenchToTheBit) {
  const std::string ur = example("ur_like/ur_like.urdf");
  const std::string offset = "1.5,-2,0.5,0.1,-0.2,0.05";
  const std::vector<std::string> noise = {"--noise-force", "0.05", "--noise-moment", "0.005"};
  auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // Static: the PUMA at 200 poses tilted in every direction, with an offset.
  Result r = run(with({"simulate", kPumaUrdf, kHoldout, "-o", path("static.csv"), "--offset",
                       offset, "--seed", "3"},
                      noise));
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kPumaUrdf, path("static.csv"), "--offset", "-o", path("static.json")});
  ASSERT_EQ(r.code, 0) << r;
  // Motion: the UR-like arm along an exciting trajectory, tilting.
  r = run({"design", ur, "--dynamic", "-o", path("traj.csv"), "--duration", "6", "--rate", "100",
           "--seed", "2", "--evaluations", "200", "--tilt-max", "20"});
  ASSERT_EQ(r.code, 0) << r;
  r = run(with({"simulate", ur, path("traj.csv"), "-o", path("motion.csv"), "--dynamic", "--offset",
                offset, "--seed", "4"},
               noise));
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", ur, path("motion.csv"), "--dynamic", "--offset", "--sigma-force", "0.05",
           "--sigma-moment", "0.005", "-o", path("motion.json")});
  ASSERT_EQ(r.code, 0) << r;

  for (const auto& [urdf, name] : {std::pair{kPumaUrdf, std::string("static")}, {ur, "motion"}}) {
    SCOPED_TRACE(name);
    const std::string log = path(name + ".csv"), params = path(name + ".json");
    r = run({"predict", urdf, params, log, "-o", path(name + "_pred.csv")});
    ASSERT_EQ(r.code, 0) << r;
    Live live({"compensate", urdf, params});
    live.send(read_file(log));
    live.close_input();
    ASSERT_EQ(live.wait(), 0) << live.err;
    write_file(path(name + "_comp.csv"), live.out);
    const Table pred = read_table(path(name + "_pred.csv"));
    const Table comp = read_table(path(name + "_comp.csv"));

    // The library, as the doors use it.
    const massid::IdentifiedModel model = massid::IdentifiedModel::load(urdf, params);
    EXPECT_EQ(model.dynamic(), name == "motion");
    EXPECT_TRUE(model.has_offset());
    massid::Samples s =
        massid::read_samples(model.model(), massid::read_csv(log), massid::WrenchColumns::Required);
    if (model.dynamic()) s = massid::prepare_motion_samples(model.model(), std::move(s), {});
    massid::IdentifiedModelData data(model);
    const Eigen::MatrixXd P = model.predict_samples(data, s);
    const Eigen::MatrixXd C = model.compensate_rows(s.wrench, P);

    ASSERT_EQ(pred.rows.size(), static_cast<size_t>(s.size()));
    ASSERT_EQ(comp.rows.size(), static_cast<size_t>(s.size()));
    double largest = 0.0;  // the offset matters: without it fx_comp would be about 1.5
    for (size_t i = 0; i < pred.rows.size(); ++i)
      for (int k = 0; k < 6; ++k) {
        const std::string c = std::string(kWrench[k]) + "_comp";
        const double from_predict = pred.num(i, c), from_compensate = comp.num(i, c);
        const double from_library = C(static_cast<Eigen::Index>(i), k);
        EXPECT_EQ(from_predict, from_library) << c << " row " << i;
        EXPECT_EQ(from_compensate, from_library) << c << " row " << i;
        EXPECT_EQ(pred.num(i, std::string(kWrench[k]) + "_pred"),
                  P(static_cast<Eigen::Index>(i), k))
            << kWrench[k] << "_pred row " << i;
        largest = std::max(largest, std::abs(from_library));
      }
    // measured - predicted - offset: the noise (and the fit's error), small.
    EXPECT_LT(largest, 0.5);
  }
}

}  // namespace
}  // namespace massid_cli_test

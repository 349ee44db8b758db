#include "compensate_command.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "latency_histogram.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "massid/live/identified_model.hpp"
#include "options.hpp"
#include "python_report.hpp"

namespace massid::cli {

void add_compensate_command(CLI::App& app, CompensateCommand& c) {
  c.app = app.add_subcommand(
      "compensate",
      "Live gravity compensation: CSV samples on stdin (or UDP), each written back with "
      "fx_comp..mz_comp");
  CLI::App* s = c.app;
  s->add_option("robot", c.urdf, "Robot URDF")->required();
  s->add_option("params", c.params, "Params JSON from identify")->required();
  s->add_option("--udp", c.udp_port,
                "Read one line per UDP datagram on 127.0.0.1:PORT (0: a free port, printed on "
                "stderr) instead of stdin; an empty datagram or 'end' ends the stream")
      ->check(CLI::Range(0, 65535));
  s->add_flag("--reply", c.reply,
              "With --udp: also send each output line back to the sender of its datagram");
  s->add_flag("--stats", c.stats,
              "At the end, print the added latency per sample (parse + predict + format: median, "
              "99.9th percentile, max) on stderr");
  s->add_option("--root-gravity", c.root_gravity,
                "Gravity in the URDF root frame, gx,gy,gz (default 0,0,-9.80665): a sensor below "
                "movable joints whose columns the stream has");
  add_level_gravity_option(s, c.level_gravity);
  s->add_flag("--track", c.track,
              "Also track a payload on a link and the sensor's drifting offsets (needs t): "
              "payload_m .. event columns after fx_comp..mz_comp, which become the external "
              "wrench (docs/tracking.md)");
  s->add_option("--payload-link", c.payload_link,
                "With --track: the payload's link (default: the measured link farthest from the "
                "sensor)");
  s->add_option("--sigma-force", c.sigma_force,
                "With --track: the sensor's force noise, N per axis (default: the params file's "
                "residual RMS)")
      ->check(CLI::PositiveNumber);
  s->add_option("--sigma-moment", c.sigma_moment,
                "With --track: the sensor's moment noise, N m per axis (default: the params "
                "file's residual RMS)")
      ->check(CLI::PositiveNumber);
  s->add_option("--report", c.report,
                "With --track: at the end of the stream, write an HTML report of the tracked log "
                "(estimates, events, compensated wrench; needs Python with matplotlib)");
  add_columns_option(s, c.columns);
}

namespace {

volatile std::sig_atomic_t g_stop = 0;  // SIGINT or SIGTERM received
extern "C" void on_stop_signal(int) { g_stop = 1; }

// SIGINT and SIGTERM end the stream (blocking reads return EINTR); a closed
// stdout ends it too (EPIPE instead of death by SIGPIPE).
void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

// Waits until fd is readable, the stop flag is set (false) or, with a
// signal arriving just before the wait, within 200 ms.
bool wait_readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  while (!g_stop) {
    const int r = ::poll(&p, 1, 200);
    if (r > 0) return true;
    if (r < 0 && errno != EINTR) return true;  // let the read report it
  }
  return false;
}

// The whole of [data, data + size) to fd; false when the reader is gone.
bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// Lines of standard input, read with read(2) into a buffer kept between
// calls (it grows only for a line longer than any before).
class StdinLines {
 public:
  static constexpr bool kEnds = true;  // a file or a pipe: contact notes at its end
  std::string name() const { return "stdin"; }
  // The next line without its '\n' and its 1-based number; false at the end.
  // The line stays valid until the next call.
  bool next(std::string_view& line, int& number) {
    std::size_t scan = begin_;
    while (true) {
      const void* nl = std::memchr(buffer_.data() + scan, '\n', end_ - scan);
      if (nl) {
        const std::size_t at =
            static_cast<std::size_t>(static_cast<const char*>(nl) - buffer_.data());
        line = std::string_view(buffer_.data() + begin_, at - begin_);
        begin_ = at + 1;
        number = ++line_;
        return true;
      }
      scan = end_;
      if (eof_ || !wait_readable(0)) break;
      if (begin_ > 0) {  // keep the unfinished line at the front
        std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
        end_ -= begin_;
        scan -= begin_;
        begin_ = 0;
      }
      if (buffer_.size() - end_ < 4096) buffer_.resize(2 * buffer_.size());
      const ssize_t n = ::read(0, buffer_.data() + end_, buffer_.size() - end_);
      if (n > 0) end_ += static_cast<std::size_t>(n);
      if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) eof_ = true;
    }
    if (begin_ == end_ || g_stop) return false;
    line = std::string_view(buffer_.data() + begin_, end_ - begin_);  // a last line without '\n'
    begin_ = end_;
    number = ++line_;
    return true;
  }
  void reply(std::string_view) {}

 private:
  std::vector<char> buffer_ =
      std::vector<char>(1 << 16);  // read but not yet returned: [begin_, end_)
  std::size_t begin_ = 0, end_ = 0;
  int line_ = 0;
  bool eof_ = false;
};

// One line per datagram on 127.0.0.1:port; an empty datagram or "end" ends.
class UdpLines {
 public:
  static constexpr bool kEnds = false;  // a live stream: no notes on the whole
  UdpLines(int port, bool reply) : reply_(reply) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw InputError(fmt::format("--udp: cannot open a socket: {}", strerror(errno)));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
      const int e = errno;
      ::close(fd_);
      throw InputError(
          fmt::format("--udp {}: cannot bind 127.0.0.1:{}: {}", port, port, strerror(e)));
    }
    socklen_t len = sizeof addr;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
    port_ = ntohs(addr.sin_port);
  }
  ~UdpLines() { ::close(fd_); }
  UdpLines(const UdpLines&) = delete;
  UdpLines& operator=(const UdpLines&) = delete;
  int port() const { return port_; }
  std::string name() const { return "udp"; }
  bool next(std::string_view& line, int& number) {
    while (wait_readable(fd_)) {
      sender_len_ = sizeof sender_;
      const ssize_t n = ::recvfrom(fd_, buffer_, sizeof buffer_, 0,
                                   reinterpret_cast<sockaddr*>(&sender_), &sender_len_);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw InputError(fmt::format("--udp: receive failed: {}", strerror(errno)));
      }
      line = std::string_view(buffer_, static_cast<std::size_t>(n));
      if (!line.empty() && line.back() == '\n') line.remove_suffix(1);
      if (line.empty() && n == 0) return false;
      if (line == "end" || line == "end\r") return false;
      number = ++datagram_;
      return true;
    }
    return false;
  }
  void reply(std::string_view out) {
    if (reply_)
      ::sendto(fd_, out.data(), out.size(), 0, reinterpret_cast<const sockaddr*>(&sender_),
               sender_len_);
  }

 private:
  int fd_ = -1, port_ = 0, datagram_ = 0;
  bool reply_ = false;
  char buffer_[65536];
  sockaddr_in sender_{};
  socklen_t sender_len_ = 0;
};

using Clock = std::chrono::steady_clock;

// The compensated rows of a stream that ends, for find_contact_episodes at
// its end (the same rule as predict's notes: a robust scale per axis over
// every row, so the rows are kept, not a running statistic). Kept in blocks
// of 4096 rows (no copy as the stream grows: one allocation per block, after
// the line is written and outside the timed part), up to kMaxRows rows
// (56 bytes each, ~117 MB); rows beyond are not judged, and the note says so.
class ContactLog {
 public:
  static constexpr std::size_t kBlock = 4096;
  static constexpr std::size_t kMaxRows = std::size_t{1} << 21;

  void add(int line, const Wrench& compensated, const Eigen::Ref<const Wrench>& measured) {
    if (rows_ == kMaxRows) {
      ++beyond_;
      return;
    }
    if (rows_ % kBlock == 0) blocks_.push_back(std::make_unique<Row[]>(kBlock));
    Row& r = blocks_.back()[rows_ % kBlock];
    r.line = line;
    for (int k = 0; k < 6; ++k) r.c[k] = compensated[k];
    squares_[0] += measured.head<3>().squaredNorm();
    squares_[1] += measured.tail<3>().squaredNorm();
    ++rows_;
  }

  // The notes, on stderr.
  void print_notes(const std::string& source) const {
    if (rows_ < 2) return;
    const Eigen::Index n = static_cast<Eigen::Index>(rows_);
    std::vector<int> line(rows_);
    Eigen::MatrixXd residual(n, 6);
    for (std::size_t i = 0; i < rows_; ++i) {
      const Row& r = blocks_[i / kBlock][i % kBlock];
      line[i] = r.line;
      for (int k = 0; k < 6; ++k) residual(static_cast<Eigen::Index>(i), k) = r.c[k];
    }
    const Eigen::Vector2d rms(std::sqrt(squares_[0] / static_cast<double>(n)),
                              std::sqrt(squares_[1] / static_cast<double>(n)));
    for (const ContactEpisode& e : find_contact_episodes(line, residual, rms))
      std::cerr << "massid: note: " << contact_note(source, e) << "\n";
    if (beyond_ > 0)
      std::cerr << fmt::format(
          "massid: note: {}: contact judged over the first {} samples (to line {}); the {} "
          "after them were compensated but not judged\n",
          source, rows_, line.back(), beyond_);
  }

 private:
  struct Row {
    int line;
    double c[6];
  };
  std::vector<std::unique_ptr<Row[]>> blocks_;
  std::size_t rows_ = 0, beyond_ = 0;
  double squares_[2] = {0.0, 0.0};  // sums of |f|^2 and |m|^2 measured
};

template <class Lines>
int run_stream(const CompensateCommand& c, const IdentifiedModel& identified,
               const CompensatorOptions& options, Lines& lines) {
  // --report: the output is spooled as it is written, and drawn at the end.
  std::optional<TrackReport> report;
  if (!c.report.empty()) {
    std::string time = "t";
    for (const auto& [role, name] : options.columns.bind)
      if (role == "t") time = name;
    report.emplace(c.report, lines.name(), time);
  }
  // The header: the first line that is neither blank nor a comment.
  std::string_view line;
  int number = 0;
  std::string text;  // blank lines for those before the header, then the header
  while (true) {
    if (!lines.next(line, number))
      throw InputError(fmt::format("{}: the stream ended before its header line", lines.name()));
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string_view::npos && line[first] != '#') break;
    text += '\n';
  }
  text += line;
  Compensator comp(identified, text, lines.name(), options);
  // One "massid: note: " line per note.
  std::istringstream notes(comp.note());
  for (std::string note; std::getline(notes, note);) std::cerr << "massid: note: " << note << "\n";
  std::cerr << std::flush;
  if (report) report->write(comp.output_header());
  if (!write_all(1, comp.output_header().data(), comp.output_header().size()))
    return report ? report->render() : 0;

  LatencyHistogram latency, tracker_latency;
  ContactLog contact;
  long skipped = 0;
  while (lines.next(line, number)) {
    const Clock::time_point t0 = c.stats ? Clock::now() : Clock::time_point{};
    std::string_view out;
    try {
      out = comp.compensate(line, number);
    } catch (const InputError& e) {
      ++skipped;
      std::cerr << "massid: " << e.what() << " (skipped)\n";
      continue;
    }
    if (out.empty()) continue;  // a comment
    if (c.stats) {
      latency.record(
          std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
      if (comp.tracker()) tracker_latency.record(comp.tracker_update_ns());
    }
    if (report) report->write(out);                    // outside the timed part
    if (!write_all(1, out.data(), out.size())) break;  // the reader is gone
    lines.reply(out);
    if constexpr (Lines::kEnds) contact.add(number, comp.compensated(), comp.measured());
  }
  if constexpr (Lines::kEnds) contact.print_notes(lines.name());
  if (c.stats)
    std::cerr << fmt::format(
        "massid: compensate: {} samples, {} lines skipped; added latency (parse, predict, "
        "format) median {:.3f} us, 99.9th percentile {:.3f} us, max {:.3f} us\n",
        latency.count(), skipped, latency.percentile(0.5) * 1e-3, latency.percentile(0.999) * 1e-3,
        static_cast<double>(latency.max()) * 1e-3);
  if (c.stats && comp.tracker())
    std::cerr << fmt::format(
        "massid: compensate: tracker update (its part of the latency) median {:.3f} us, 99.9th "
        "percentile {:.3f} us, max {:.3f} us\n",
        tracker_latency.percentile(0.5) * 1e-3, tracker_latency.percentile(0.999) * 1e-3,
        static_cast<double>(tracker_latency.max()) * 1e-3);
  return report ? report->render() : 0;
}

}  // namespace

int run_compensate(const CompensateCommand& c) {
  if (c.reply && c.udp_port < 0) throw InputError("--reply goes with --udp PORT");
  if (!c.track && (!c.payload_link.empty() || c.sigma_force > 0 || c.sigma_moment > 0))
    throw InputError("--payload-link, --sigma-force and --sigma-moment go with --track");
  if (!c.track && !c.report.empty())
    throw InputError("compensate --report draws a tracked log: it goes with --track");
  if (!c.report.empty()) {  // before any work: the report comes at the end of the stream
    const std::filesystem::path dir = std::filesystem::absolute(c.report).parent_path();
    if (::access(dir.c_str(), W_OK) != 0)
      throw InputError(fmt::format("--report {}: cannot write into {} ({})", c.report, dir.string(),
                                   std::strerror(errno)));
    check_report_tools();
  }
  const ParamsFile params = read_params(c.params);
  const IdentifiedModel identified = IdentifiedModel::load(c.urdf, params);
  CompensatorOptions options;
  if (c.track) {
    // The sensor noise: given, else the fit's residual RMS per axis, else the
    // tracker's default.
    options.track = true;
    options.time_tracker = c.stats;
    options.tracker.payload_link = c.payload_link;
    options.tracker.noise = tracker_noise(identified.residual_rms(), c.sigma_force, c.sigma_moment);
  }
  if (!c.root_gravity.empty())
    options.root_gravity = parse_numbers<3>(c.root_gravity, "--root-gravity", "gx,gy,gz");
  options.level_gravity = parse_level_gravity(c.level_gravity);
  options.columns = parse_columns(c.columns);
  install_signal_handlers();
  if (c.udp_port >= 0) {
    UdpLines lines(c.udp_port, c.reply);
    std::cerr << fmt::format("massid: compensate: listening on udp 127.0.0.1:{}\n", lines.port())
              << std::flush;
    return run_stream(c, identified, options, lines);
  }
  StdinLines lines;
  return run_stream(c, identified, options, lines);
}

}  // namespace massid::cli

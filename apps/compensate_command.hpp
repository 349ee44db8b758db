// `massid compensate`: live gravity compensation as a filter. A CSV header,
// then sample lines from standard input (or one line per UDP datagram on
// 127.0.0.1:PORT); each good sample is written to stdout, flushed, as the
// input columns plus fx_comp..mz_comp (compensator.hpp). A bad line is named
// on stderr and skipped; end of input, an empty datagram or "end", SIGINT or
// SIGTERM end the stream (exit 0); --stats then prints the added latency.
// With --track --report, the HTML report of the tracked log is drawn then
// (python_report.hpp's TrackReport).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace massid::cli {

struct CompensateCommand {
  CLI::App* app = nullptr;
  std::string urdf, params;
  int udp_port = -1;          // -1: standard input; 0: any free port (printed)
  bool reply = false;         // --reply: each output line also sent back to the datagram's sender
  bool stats = false;         // --stats: the latency figures on stderr at the end
  std::string root_gravity;   // --root-gravity gx,gy,gz (root frame; upstream joints)
  std::string level_gravity;  // --gravity gx,gy,gz (sensor frame, level; tilt columns)
  std::vector<std::string> columns;  // --columns ROLE=NAME,...
  bool track = false;                // --track: the payload and the offsets (tracker.hpp)
  std::string payload_link;          // --payload-link LINK ("" = the farthest measured link)
  double sigma_force = 0.0, sigma_moment = 0.0;  // --sigma-force/--sigma-moment (0: the params')
  std::string report;  // --report REPORT.html (with --track): drawn at the end of the stream
};

void add_compensate_command(CLI::App& app, CompensateCommand& cmd);
int run_compensate(const CompensateCommand& cmd);

}  // namespace massid::cli

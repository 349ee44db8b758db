// `--report REPORT.html` of identify, predict and compensate --track: the HTML report is drawn by
// the Python package (python -m massid.report, matplotlib), which the CLI runs
// as a child process.
//
// Interpreter: $MASSID_PYTHON, else the one the build was configured with
// (/usr/bin/python3 by default). The package: the build tree's
// <dir of massid>/python is put first on PYTHONPATH when it holds one; an
// installed package is found by the interpreter itself.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "massid/identify/identification.hpp"

namespace massid::cli {

// Throws InputError with what is missing (Python, numpy, matplotlib or the
// massid package) and how to get it. Run before any work.
void check_report_tools();

// Runs `python -m massid.report ARGS...`; its own messages go to stderr
// (and with to_stderr its stdout too). Returns its exit code (0, 2 bad input,
// 3 not identifiable; 1 otherwise).
int run_report(const std::vector<std::string>& args, bool to_stderr = false);

// identify --report: the identification is written to a temporary record
// (write_identification, removed afterwards) and drawn by
// `python -m massid.report draw-identify RECORD -o REPORT`: the report shows
// the fit the command printed, without fitting again.
int run_identify_report(const Identification& ident, const std::string& report);

// compensate --track --report: the output (header and rows) is spooled, as it
// is written, to a temporary file (massid-track-XXXXXX in the temporary
// directory: nothing is held in memory), and drawn at the end of the stream by
// `python -m massid.report track SPOOL -o REPORT` (its "wrote" line on
// stderr: stdout is the data). The spool is removed on destruction.
class TrackReport {
 public:
  // source: the stream's name as the report shows it; time_column: the name
  // of the time column in the output.
  TrackReport(std::string report, std::string source, std::string time_column);
  ~TrackReport();
  TrackReport(const TrackReport&) = delete;
  TrackReport& operator=(const TrackReport&) = delete;
  void write(std::string_view text);
  // Closes the spool and draws the report; run_report's exit code. Throws
  // InputError when the spool could not be written (a full disk).
  int render();

 private:
  std::string report_, source_, time_, spool_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;
  int error_ = 0;
};

}  // namespace massid::cli

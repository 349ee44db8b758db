// `--report REPORT.html` of identify and predict: the HTML report is drawn by
// the Python package (python -m massid.report, matplotlib), which the CLI runs
// as a child process.
//
// Interpreter: $MASSID_PYTHON, else the one the build was configured with
// (/usr/bin/python3 by default). The package: the build tree's
// <dir of massid>/python is put first on PYTHONPATH when it holds one; an
// installed package is found by the interpreter itself.
#pragma once

#include <string>
#include <vector>

#include "massid/identify/identification.hpp"

namespace massid::cli {

// Throws InputError with what is missing (Python, numpy, matplotlib or the
// massid package) and how to get it. Run before any work.
void check_report_tools();

// Runs `python -m massid.report ARGS...`; its own messages go to stderr.
// Returns its exit code (0, 2 bad input, 3 not identifiable; 1 otherwise).
int run_report(const std::vector<std::string>& args);

// identify --report: the identification is written to a temporary record
// (write_identification, removed afterwards) and drawn by
// `python -m massid.report draw-identify RECORD -o REPORT`: the report shows
// the fit the command printed, without fitting again.
int run_identify_report(const Identification& ident, const std::string& report);

}  // namespace massid::cli

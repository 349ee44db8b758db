// `massid identify`: options, registration with CLI11, and the run. The
// options only become an IdentifyRequest (massid/identify/identify_request.hpp), whose
// rules check them; this file prints what the library returns.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "massid/identify/identify_request.hpp"

namespace massid::cli {

struct IdentifyCommand {
  CLI::App* app = nullptr;
  std::string urdf, data, output, report, urdf_out;
  std::string sensor, drift, rest, delay, root_gravity;
  std::string level_gravity;         // --gravity gx,gy,gz (sensor frame, level; tilt columns)
  std::vector<std::string> fixed;    // --fixed JOINT=VALUE
  std::vector<std::string> columns;  // --columns ROLE=NAME,...
  double cutoff = 0.0, sigma_force = 0.0, sigma_moment = 0.0;
  int physical_iterations = 0;  // --physical-iterations (0: the solver's default)
  bool offset = false, dynamic = false, robust = false, physical = false, no_checks = false;
  bool accept_unconverged = false;

  // The options as a request (not yet validated).
  IdentifyRequest request() const;
};

void add_identify_command(CLI::App& app, IdentifyCommand& cmd);
int run_identify(const IdentifyCommand& cmd);

}  // namespace massid::cli

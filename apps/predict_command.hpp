// `massid predict`: options, registration with CLI11, and the run.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "command_support.hpp"

namespace massid::cli {

struct PredictCommand {
  CLI::App* app = nullptr;
  std::string urdf, params, data, output, report;
  MotionFlags motion;                // --root-gravity, --cutoff
  std::vector<std::string> columns;  // --columns ROLE=NAME,...
  bool no_checks = false, physical = false;
};

void add_predict_command(CLI::App& app, PredictCommand& cmd);
int run_predict(const PredictCommand& cmd);

}  // namespace massid::cli

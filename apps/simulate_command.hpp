// `massid simulate`: options, registration with CLI11, and the run.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "command_support.hpp"
#include "massid/core/simulate.hpp"

namespace massid::cli {

struct SimulateCommand {
  CLI::App* app = nullptr;
  std::string urdf, sensor, plan, output;
  std::string sensor_offset;  // --sensor-offset fx,fy,fz,mx,my,mz
  std::string old_offset;     // --offset fx,..,mz: --sensor-offset's old spelling
  SimulateOptions sim;
  MotionFlags motion;
  std::vector<std::string> columns;  // --columns ROLE=NAME,...
  std::vector<std::string> fixed;    // --fixed JOINT=VALUE: held still, its column not read
  bool no_checks = false;
};

void add_simulate_command(CLI::App& app, SimulateCommand& cmd);
int run_simulate(SimulateCommand cmd);

}  // namespace massid::cli

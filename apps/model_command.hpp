// `massid model`: options, registration with CLI11, and the run.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "command_support.hpp"

namespace massid::cli {

struct ModelCommand {
  CLI::App* app = nullptr;
  std::string urdf, sensor;
  std::vector<std::string> fixed;  // --fixed JOINT=VALUE
  bool offset = false, as_json = false;
  MotionFlags motion;
  std::string old_gravity_model;  // --gravity level|varying: --gravity-model's old spelling
};

void add_model_command(CLI::App& app, ModelCommand& cmd);
int run_model(ModelCommand cmd);

}  // namespace massid::cli

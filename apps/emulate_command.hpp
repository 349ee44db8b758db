// `massid emulate`: the space emulator in simulation, three runs side by side.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace massid::cli {

struct EmulateCommand {
  CLI::App* app = nullptr;
  std::string urdf, params, output, summary, platform, inertia = "5,5,5", trajectory, gravity,
                                                       plant;
  double mass = 50.0, duration = 10.0, rate = 1000.0;
  bool no_tare = false;
};

void add_emulate_command(CLI::App& app, EmulateCommand& cmd);
int run_emulate(const EmulateCommand& cmd);

}  // namespace massid::cli

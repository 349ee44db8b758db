// `massid design`: options, registration with CLI11, and the run.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace massid::cli {

struct DesignCommand {
  CLI::App* app = nullptr;
  std::string urdf, sensor, output, evaluate, tilts, gravity, criterion = "cond";
  std::vector<std::string> fixed, limits;
  std::string min_height;      // a number (m) or "none"
  std::string self_clearance;  // --dynamic, a wrist: a number (m) or "none"
  std::string root_gravity;    // a wrist: --root-gravity gx,gy,gz (URDF root frame)
  int poses = 0, candidates = 0, tilt_groups = 4, level_poses = -1;
  double tilt_max_deg = 0.0, noise_force = 0.05, noise_moment = 0.005;
  bool offset = false;
  unsigned long long seed = 1;
  // --dynamic: an exciting trajectory (excitation.hpp)
  bool dynamic = false;
  bool no_checks = false;            // --evaluate: skip the file's set-up checks
  std::vector<std::string> columns;  // --evaluate: --columns ROLE=NAME,...
  double duration = 30.0, rate = 1000.0, period = 10.0;
  int harmonics = 5, evaluations = 6000;
  std::vector<std::string> velocity_limits, acceleration_limits;
};

void add_design_command(CLI::App& app, DesignCommand& cmd);
int run_design(const DesignCommand& cmd);

}  // namespace massid::cli

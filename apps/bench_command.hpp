// `massid bench`: times the real-time and identification paths on this
// machine and robot, so users can size their control loop.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace massid::cli {

struct BenchCommand {
  CLI::App* app = nullptr;
  std::string urdf, sensor;
  int rows = 100000;
  bool json = false;
};

void add_bench_command(CLI::App& app, BenchCommand& cmd);
int run_bench(const BenchCommand& cmd);

}  // namespace massid::cli

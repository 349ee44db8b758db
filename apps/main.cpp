// The massid command-line tool: parses arguments, calls the library, prints
// its summaries. Exit codes: 0 success, 2 bad usage or input, 3 the data cannot
// determine the parameters, 1 an internal error.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "bench_command.hpp"
#include "compensate_command.hpp"
#include "design_command.hpp"
#include "emulate_command.hpp"
#include "hints.hpp"
#include "identify_command.hpp"
#include "massid/core/errors.hpp"
#include "massid/version.hpp"
#include "model_command.hpp"
#include "predict_command.hpp"
#include "simulate_command.hpp"

using namespace massid;
using namespace massid::cli;

int main(int argc, char** argv) {
  CLI::App app{
      "massid: mass parameters of a mechanism on a force/torque sensor, from static wrenches "
      "and in motion"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "massid " MASSID_VERSION);

  ModelCommand model;
  add_model_command(app, model);
  SimulateCommand simulate;
  add_simulate_command(app, simulate);
  IdentifyCommand identify;
  add_identify_command(app, identify);
  PredictCommand predict;
  add_predict_command(app, predict);
  DesignCommand design;
  add_design_command(app, design);
  EmulateCommand emulate;
  add_emulate_command(app, emulate);
  BenchCommand bench;
  add_bench_command(app, bench);
  CompensateCommand compensate;
  add_compensate_command(app, compensate);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, like every other error.
    const auto subs = app.get_subcommands();
    std::cerr << fmt::format("massid: error: {} (see massid {}--help)\n", e.what(),
                             subs.empty() ? "" : subs.front()->get_name() + " ");
    return 2;
  }

  try {
    if (*model.app) return run_model(model);
    if (*simulate.app) return run_simulate(simulate);
    if (*identify.app) return run_identify(identify);
    if (*predict.app) return run_predict(predict);
    if (*design.app) return run_design(design);
    if (*emulate.app) return run_emulate(emulate);
    if (*bench.app) return run_bench(bench);
    if (*compensate.app) return run_compensate(compensate);
  } catch (const InputError& e) {
    std::cerr << "massid: error: " << cli::with_hints(e.what(), e.hints()) << "\n";
    return 2;
  } catch (const IdentifiabilityError& e) {
    std::cerr << "massid: error: " << cli::with_hints(e.what(), e.hints()) << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "massid: internal error: " << e.what() << "\n";
    return 1;
  }
  return 2;
}

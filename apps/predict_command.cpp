#include "predict_command.hpp"

#include <fmt/format.h>

#include <iostream>

#include "massid/core/errors.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/predict_log.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/live/identified_model.hpp"
#include "massid/report/report.hpp"
#include "python_report.hpp"

namespace massid::cli {

namespace {

int run_predict(const std::string& urdf, const std::string& params_path,
                const std::string& data_path, const std::string& out, const std::string& report,
                const MotionFlags& motion, const std::vector<std::string>& columns, bool checks,
                bool physical) {
  if (!report.empty() && physical)
    throw InputError("predict --report draws the identified base parameters: drop --physical");
  if (!report.empty()) check_report_tools();  // before any work
  // The identified base parameters, or with --physical K pi of the physical ones.
  IdentifiedModelOptions iopts;
  iopts.physical = physical;
  const IdentifiedModel identified = IdentifiedModel::load(urdf, params_path, iopts);
  const Model& model = identified.model();

  // The library's pipeline (predict_log.hpp); this door prints and writes.
  PredictLogOptions popts;
  popts.motion = motion.data();
  popts.motion.samples.columns = parse_columns(columns);
  popts.checks = checks;
  popts.on_verdict = [](const SetupVerdict& v) { report_setup(v.findings); };
  LogPrediction lp;
  try {
    lp = predict_log(identified, read_csv(data_path), data_path, popts);
  } catch (const SetupRefused&) {
    return 2;  // on_verdict printed the errors, each on its own line
  }
  print_column_note(lp.column_note);
  const Samples& samples = lp.samples;
  if (lp.motion.derived)
    std::cout << fmt::format(
        "velocities and accelerations derived from t and the positions: zero-phase low-pass "
        "at {:.3g} Hz, the {} rows at each end dropped\n",
        lp.motion.kernels.cutoff, lp.motion.kernels.half_width);
  if (!out.empty()) {
    OutputTable t(lp.table);
    // _pred: the mechanism's wrench alone; _comp: measured - predicted - offset.
    for (int k = 0; k < 6; ++k)
      t.set_column(std::string(kWrenchColumns[k]) + "_pred", lp.predicted.col(k));
    if (lp.has_wrench())
      for (int k = 0; k < 6; ++k)
        t.set_column(std::string(kWrenchColumns[k]) + "_comp", lp.compensated.col(k));
    write_csv(out, t.header, t.rows);
  }
  std::cout << fmt::format("predicted {} samples of {} with {}{} (sensor link '{}'{})\n",
                           samples.size(), data_path, params_path,
                           physical ? "'s physical parameters" : "", model.sensor_link(),
                           samples.gravity_from_force ? ", gravity from the measured force" : "");
  if (lp.has_wrench()) {
    // Against what the sensor reads: the prediction plus the identified offset.
    const Eigen::MatrixXd reading = identified.sensor_reading_rows(lp.predicted);
    std::cout << prediction_report(prediction_errors(samples.wrench, reading), samples.size());
    // Rows that carry an external wrench (contact) are the expected result here: a note.
    for (const std::string& note : lp.notes) std::cerr << "massid: note: " << note << "\n";
  }
  if (!out.empty()) std::cout << "wrote " << out << "\n";
  if (!report.empty()) {
    std::vector<std::string> a{"predict", urdf, params_path, data_path, "-o", report};
    for (const std::string& m : motion.report_args()) a.push_back(m);
    for (const std::string& m : columns) a.insert(a.end(), {"--columns", m});
    return run_report(a);
  }
  return 0;
}

}  // namespace

void add_predict_command(CLI::App& app, PredictCommand& c) {
  c.app = app.add_subcommand("predict", "Gravity wrench predicted at every row of a CSV");
  CLI::App* pred = c.app;
  pred->add_option("robot", c.urdf, "Robot URDF")->required();
  pred->add_option("params", c.params, "Params JSON from identify")->required();
  pred->add_option("data", c.data, "Plan or data CSV")->required();
  pred->add_option("-o,--output", c.output, "CSV to write: input plus *_pred (and *_comp)");
  pred->add_option("--report", c.report,
                   "Also write an HTML report (plots; needs Python with matplotlib)");
  pred->add_option("--root-gravity", c.motion.root_gravity,
                   "Gravity in the URDF root frame, gx,gy,gz (sensor below movable joints)");
  add_level_gravity_option(pred, c.motion.level_gravity);
  pred->add_option("--cutoff", c.motion.cutoff,
                   "Dynamic params, log without JOINT_vel/_acc: low-pass cutoff, Hz")
      ->check(CLI::PositiveNumber);
  pred->add_flag("--physical", c.physical,
                 "Predict from the params file's physical parameters (identify --physical) "
                 "instead of its base parameters");
  pred->add_flag("--no-checks", c.no_checks,
                 "Skip the file's set-up checks (joint and wrench units, signs, frame, columns)");
  add_columns_option(pred, c.columns);
}

int run_predict(const PredictCommand& c) {
  return run_predict(c.urdf, c.params, c.data, c.output, c.report, c.motion, c.columns,
                     !c.no_checks, c.physical);
}

}  // namespace massid::cli

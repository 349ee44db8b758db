#include "predict_command.hpp"

#include <fmt/format.h>

#include <iostream>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/live/identified_model.hpp"
#include "massid/report/report.hpp"
#include "python_report.hpp"

namespace massid::cli {

namespace {

int run_predict(const std::string& urdf, const std::string& params_path,
                const std::string& data_path, const std::string& out, const std::string& report,
                const MotionFlags& motion, bool checks, bool physical) {
  if (!report.empty() && physical)
    throw InputError("predict --report draws the identified base parameters: drop --physical");
  if (!report.empty()) check_report_tools();  // before any work
  // The identified base parameters, or with --physical K pi of the physical ones.
  IdentifiedModelOptions iopts;
  iopts.physical = physical;
  const IdentifiedModel identified = IdentifiedModel::load(urdf, params_path, iopts);
  const Model& model = identified.model();

  CsvTable table = read_csv(data_path);
  Samples samples;
  if (identified.dynamic()) {
    // The full wrench, weight and motion, from the dynamic base parameters.
    MotionDataReport mr;
    MotionDataOptions mopts = motion.data();
    mopts.filter.decimation = 1;  // a prediction for every row the filter keeps
    Samples raw = read_samples(model, table, WrenchColumns::Optional, mopts.samples);
    if (checks && !check_input(model, raw, table.header, true)) return 2;
    samples = prepare_motion_samples(model, std::move(raw), mopts, &mr);
    if (mr.derived) {
      std::cout << fmt::format(
          "velocities and accelerations derived from t and the positions: zero-phase low-pass "
          "at {:.3g} Hz, the {} rows at each end dropped\n",
          mr.kernels.cutoff, mr.kernels.half_width);
      table = keep_lines(std::move(table), samples.line);
    }
  } else {
    samples = read_samples(model, table, WrenchColumns::Optional, motion.data().samples);
    if (checks && !check_input(model, samples, table.header, false)) return 2;
  }
  // The mechanism's wrench alone (_pred); what the sensor reads adds the offset.
  IdentifiedModelData data(identified);
  const Eigen::MatrixXd P = identified.predict_samples(data, samples);
  if (!out.empty()) {
    OutputTable t(table);
    // _pred: the mechanism's wrench alone; _comp: measured - predicted - offset.
    for (int k = 0; k < 6; ++k) t.set_column(std::string(kWrenchColumns[k]) + "_pred", P.col(k));
    if (samples.has_wrench()) {
      const Eigen::MatrixXd C = identified.compensate_rows(samples.wrench, P);
      for (int k = 0; k < 6; ++k) t.set_column(std::string(kWrenchColumns[k]) + "_comp", C.col(k));
    }
    write_csv(out, t.header, t.rows);
  }
  std::cout << fmt::format("predicted {} samples of {} with {}{} (sensor link '{}'{})\n",
                           samples.size(), data_path, params_path,
                           physical ? "'s physical parameters" : "", model.sensor_link(),
                           samples.gravity_from_force ? ", gravity from the measured force" : "");
  if (samples.has_wrench()) {
    // Against what the sensor reads: the prediction plus the identified offset.
    const Eigen::MatrixXd reading = identified.sensor_reading_rows(P);
    std::cout << prediction_report(prediction_errors(samples.wrench, reading), samples.size());
    // Rows that carry an external wrench (contact) are the expected result here: a note.
    for (const ContactEpisode& e : find_contact_episodes(samples, samples.wrench - reading))
      std::cerr << "massid: note: " << contact_note(data_path, e) << "\n";
  }
  if (!out.empty()) std::cout << "wrote " << out << "\n";
  if (!report.empty()) {
    std::vector<std::string> a{"predict", urdf, params_path, data_path, "-o", report};
    for (const std::string& m : motion.report_args()) a.push_back(m);
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
  pred->add_option("--cutoff", c.motion.cutoff,
                   "Dynamic params, log without JOINT_vel/_acc: low-pass cutoff, Hz")
      ->check(CLI::PositiveNumber);
  pred->add_flag("--physical", c.physical,
                 "Predict from the params file's physical parameters (identify --physical) "
                 "instead of its base parameters");
  pred->add_flag("--no-checks", c.no_checks,
                 "Skip the file's set-up checks (joint and wrench units, signs, frame, columns)");
}

int run_predict(const PredictCommand& c) {
  return run_predict(c.urdf, c.params, c.data, c.output, c.report, c.motion, !c.no_checks,
                     c.physical);
}

}  // namespace massid::cli

// The massid command-line tool: parses arguments, calls the library, prints
// its summaries. Exit codes: 0 success, 2 bad usage or input, 3 the data cannot
// determine the parameters, 1 an internal error.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <optional>

#include "atomic_file.hpp"
#include "bench_command.hpp"
#include "compensate_command.hpp"
#include "design_command.hpp"
#include "emulate_command.hpp"
#include "hints.hpp"
#include "identify_file.hpp"
#include "massid/base_parameters.hpp"
#include "massid/base_regressor.hpp"
#include "massid/csv.hpp"
#include "massid/errors.hpp"
#include "massid/estimation.hpp"
#include "massid/identification.hpp"
#include "massid/motion_data.hpp"
#include "massid/motion_predictor.hpp"
#include "massid/params_file.hpp"
#include "massid/predictor.hpp"
#include "massid/report.hpp"
#include "massid/samples.hpp"
#include "massid/setup_checks.hpp"
#include "massid/simulate.hpp"
#include "massid/urdf_inertials.hpp"
#include "massid/version.hpp"
#include "options.hpp"
#include "python_report.hpp"

namespace {

using namespace massid;
using namespace massid::cli;

// Appends (or overwrites) named numeric columns of a table, for writing.
struct OutputTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  explicit OutputTable(const CsvTable& in) : header(in.header), rows(in.rows) {}
  void set_column(const std::string& name, const Eigen::VectorXd& values) {
    int c = -1;
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) c = static_cast<int>(i);
    if (c < 0) {
      header.push_back(name);
      for (auto& r : rows) r.emplace_back();
      c = static_cast<int>(header.size()) - 1;
    }
    for (size_t r = 0; r < rows.size(); ++r) rows[r][c] = format_number(values[r]);
  }
};

// The rows of `table` at the given file lines (in order), for output.
CsvTable keep_lines(CsvTable table, const std::vector<int>& lines) {
  CsvTable out = std::move(table);
  std::vector<std::vector<std::string>> rows;
  std::vector<int> kept;
  size_t k = 0;
  for (int r = 0; r < out.num_rows() && k < lines.size(); ++r)
    if (out.line[r] == lines[k]) {
      rows.push_back(std::move(out.rows[r]));
      kept.push_back(out.line[r]);
      ++k;
    }
  out.rows = std::move(rows);
  out.line = std::move(kept);
  out.column_offset.clear();
  return out;
}

struct Common {
  std::string urdf, sensor;
  std::vector<std::string> fixed;  // --fixed JOINT=VALUE (model, identify)
  Model load() const { return hold_joints(load_urdf(urdf, sensor), parse_held(fixed)); }
};

// --dynamic and its motion options (model, simulate, identify, predict).
struct MotionFlags {
  bool dynamic = false;
  double cutoff = 0.0;              // --cutoff HZ (0: the default for the log's rate)
  std::string root_gravity;         // --root-gravity gx,gy,gz
  std::string gravity = "varying";  // model --dynamic: --gravity level|varying
  bool sensor_moving = false;       // model --dynamic --moving-sensor
  // The same options for `python -m massid.report predict`.
  std::vector<std::string> report_args() const {
    std::vector<std::string> a;
    if (cutoff > 0) a.insert(a.end(), {"--cutoff", format_number(cutoff)});
    if (!root_gravity.empty()) a.insert(a.end(), {"--root-gravity", root_gravity});
    return a;
  }
  MotionDataOptions data() const {
    MotionDataOptions o;
    o.filter.cutoff = cutoff;
    if (!root_gravity.empty())
      o.samples.root_gravity = parse_numbers<3>(root_gravity, "--root-gravity", "gx,gy,gz");
    return o;
  }
};

int run_model(const Common& c, bool offset, bool as_json, const MotionFlags& motion) {
  const Model model = c.load();
  BaseParameterOptions opts;
  if (motion.dynamic) {
    opts.layout = ParameterLayout::full();
    opts.fixed_gravity = motion.gravity == "level";
    opts.sensor_moving = motion.sensor_moving;
    if (!motion.root_gravity.empty()) opts.gravity = motion.data().samples.root_gravity;
  }
  opts.offset = offset;
  const BaseParameters base = find_base_parameters(model, opts);
  if (!(model.nominal_total_mass() > 0))
    std::cerr << fmt::format(
        "massid: warning: {}: no measured link has a mass (no <inertial> below sensor link "
        "'{}'): the base parameters are the URDF's structure only; simulate cannot make data "
        "from it, and identify judges units by the robot's size alone\n",
        c.urdf, model.sensor_link());
  std::cout << (as_json ? params_json(model, base, nullptr) : model_report(model, base));
  return 0;
}

int run_simulate(const Common& c, const std::string& plan_path, const std::string& out,
                 const SimulateOptions& opts, const MotionFlags& motion, bool checks) {
  const Model model = load_urdf(c.urdf, c.sensor);
  if (!(model.nominal_total_mass() > 0))
    throw InputError(fmt::format(
        "{}: no measured link has a mass (no <inertial> below sensor link '{}'): the simulated "
        "wrench would be zero; add the links' <inertial> elements (mass, origin) to the URDF",
        c.urdf, model.sensor_link()));
  const CsvTable table = read_csv(plan_path);
  const Samples plan = read_samples(model, table, WrenchColumns::Optional, motion.data().samples);
  if (plan.gravity_from_force) throw InputError(plan_path + ": simulate needs gx,gy,gz columns");
  // Joints in degrees or mm, gravity in g, ... (a wrench in the plan is replaced: not judged).
  Samples judged = plan;
  judged.wrench.resize(0, 0);
  if (checks && !check_input(model, judged, table.header, opts.dynamic)) return 2;
  if (opts.dynamic) {
    if (model.num_joints() > 0 && plan.qd.cols() != model.num_joints())
      throw InputError(fmt::format(
          "{}: simulate --dynamic needs the trajectory's velocities and accelerations: columns "
          "JOINT_vel and JOINT_acc for every joint (massid design --dynamic writes them)",
          plan_path));
    if (plan.q_upstream.cols() > 0 && plan.qd_upstream.cols() == 0 && !plan.has_sensor_motion())
      throw InputError(fmt::format(
          "{}: simulate --dynamic needs the upstream joints' _vel and _acc columns", plan_path));
  }
  const Eigen::MatrixXd W = simulate_wrenches(model, plan, opts);
  OutputTable t(table);
  if (opts.repeat > 1) {
    std::vector<std::vector<std::string>> rows;
    rows.reserve(W.rows());
    for (const auto& row : t.rows)
      for (int r = 0; r < opts.repeat; ++r) rows.push_back(row);
    t.rows = std::move(rows);
  }
  for (int k = 0; k < 6; ++k) t.set_column(kWrenchColumns[k], W.col(k));
  write_csv(out, t.header, t.rows);
  std::cout << fmt::format(
      "simulated {} samples of {} (sensor link '{}', total mass {:.6g} kg) -> {}\n", W.rows(),
      model.name, model.sensor_link(), model.nominal_total_mass(), out);
  return 0;
}

int run_identify(const Common& c, const std::string& data_path, const std::string& out, bool offset,
                 const IdentifyOptions& opts, bool checks, const std::string& report,
                 const MotionFlags& motion, const std::string& urdf_out) {
  if (!report.empty()) check_report_tools();  // before any work
  const Model model = c.load();
  // Before any work: wrong signs, units, frames or columns (the first 20 000
  // rows of a big file). A joint that never moves is left to the
  // identifiability diagnosis below, which names it with the fix.
  SetupCheckOptions sopts;
  sopts.constant_joints = false;
  sopts.motion = motion.dynamic;
  sopts.read = motion.data().samples;  // the root gravity
  if (checks && !report_setup(check_setup_file(model, data_path, sopts))) return 2;
  // With --report the samples and fitted wrenches are kept for the report,
  // which draws this fit (identification.hpp); without, any log in constant memory.
  const Identification ident =
      identify_log(model, data_path, offset, opts, motion.dynamic, motion.data(), !report.empty());
  const IdentifySummary& summary = ident.summary;
  if (ident.motion.derived)
    std::cout << fmt::format(
        "velocities and accelerations derived from t and the positions: zero-phase low-pass "
        "at {:.3g} Hz (--cutoff), {} samples at each end dropped, every {} filtered sample "
        "kept: {} of {} rows\n",
        ident.motion.kernels.cutoff, ident.motion.kernels.half_width, ident.motion.decimation,
        summary.samples, ident.motion.rows);
  // The gravity note first (when gravity came from the force), then the warnings.
  for (std::size_t i = 0; i < ident.warnings.size(); ++i)
    std::cerr << (i == 0 && summary.gravity_from_force ? "massid: note: " : "massid: warning: ")
              << cli::with_hints(ident.warnings[i].message, ident.warnings[i].hints) << "\n";
  write_file_atomically(out, params_json(ident.model, ident.base, &summary,
                                         ident.physical ? &*ident.physical : nullptr));
  std::cout << identify_report(ident.model, ident.base, summary, data_path);
  if (ident.physical) std::cout << physical_report(ident.base, *ident.physical, cli::spell);
  std::cout << "wrote " << out << "\n";
  if (!urdf_out.empty()) {
    const bool rest = ident.physical->static_layout;
    write_file_atomically(
        urdf_out,
        identified_urdf(ident.model, *ident.physical,
                        fmt::format("identified by massid from {}: {}", data_path,
                                    rest ? "mass and centre of mass at rest, the inertia about "
                                           "the centre of mass the URDF's"
                                         : "mass, centre of mass and inertia in motion")));
    std::cout << fmt::format(
        "wrote {}: {} with the physical inertials of the measured links ({}), every other byte "
        "as it was\n",
        urdf_out, c.urdf,
        rest ? "masses and centres of mass" : "masses, centres of mass, inertias");
  }
  if (!report.empty()) return run_identify_report(ident, report);
  return 0;
}

int run_predict(const std::string& urdf, const std::string& params_path,
                const std::string& data_path, const std::string& out, const std::string& report,
                const MotionFlags& motion, bool checks, bool physical) {
  if (!report.empty() && physical)
    throw InputError("predict --report draws the identified base parameters: drop --physical");
  if (!report.empty()) check_report_tools();  // before any work
  const ParamsFile params = read_params(params_path);
  const Model model = hold_joints(load_urdf(urdf, params.sensor_link), params.held);
  const BaseParameters base = find_base_parameters(model, base_parameter_options(params));
  // The identified base parameters, or with --physical K pi of the physical ones.
  const Eigen::VectorXd values = physical ? physical_values_in_basis(params, model, base)
                                          : values_in_basis(params, model, base);

  CsvTable table = read_csv(data_path);
  Samples samples;
  Eigen::MatrixXd P;  // what the sensor reads: the mechanism's wrench plus the offsets
  Wrench offset = Wrench::Zero();
  if (params.dynamic) {
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
    // The full wrench, offsets included as the static predictor does (with
    // level data they hold the weight the offsets absorbed).
    const MotionPredictor predictor = compile_motion_predictor(model, base, values);
    MotionPredictorData data(predictor);
    P = predict_samples(predictor, data, samples);
    offset = predictor.offset;
  } else {
    const Predictor predictor = compile_predictor(model, base, values);
    offset = predictor.offset;
    PredictorData data(predictor);
    samples = read_samples(model, table, WrenchColumns::Optional, motion.data().samples);
    if (checks && !check_input(model, samples, table.header, false)) return 2;
    P.resize(samples.size(), 6);
    for (int i = 0; i < samples.size(); ++i)
      P.row(i) =
          predict(predictor, data, samples.q.row(i).transpose(), samples.gravity.row(i).transpose())
              .transpose();
  }
  if (!out.empty()) {
    OutputTable t(table);
    // _pred: the mechanism's wrench alone; _comp: measured - predicted - offset.
    for (int k = 0; k < 6; ++k)
      t.set_column(std::string(kWrenchColumns[k]) + "_pred",
                   (P.col(k).array() - offset[k]).matrix());
    if (samples.has_wrench())
      for (int k = 0; k < 6; ++k)
        t.set_column(std::string(kWrenchColumns[k]) + "_comp", samples.wrench.col(k) - P.col(k));
    write_csv(out, t.header, t.rows);
  }
  std::cout << fmt::format("predicted {} samples of {} with {}{} (sensor link '{}'{})\n",
                           samples.size(), data_path, params_path,
                           physical ? "'s physical parameters" : "", model.sensor_link(),
                           samples.gravity_from_force ? ", gravity from the measured force" : "");
  if (samples.has_wrench()) {
    std::cout << prediction_report(prediction_errors(samples.wrench, P), samples.size());
    for (const ContactEpisode& e : find_contact_episodes(samples, samples.wrench - P))
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

int main(int argc, char** argv) {
  CLI::App app{
      "massid: mass parameters of a mechanism on a force/torque sensor, from static wrenches "
      "and in motion"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "massid " MASSID_VERSION);

  Common common;
  bool offset = false, as_json = false;
  std::string plan, data, out, params, offset_text;
  SimulateOptions sim;
  IdentifyOptions idopts;
  std::string drift_text, report, rest_text = "auto", delay_text, urdf_out;
  bool no_checks = false, physical = false;
  double sigma_force = 0, sigma_moment = 0;
  MotionFlags motion;
  auto add_motion = [&](CLI::App* sub, bool filter) {
    sub->add_flag("--dynamic", motion.dynamic,
                  "Motion: the full wrench (weight and motion) over ten parameters per link");
    sub->add_option("--root-gravity", motion.root_gravity,
                    "Gravity in the URDF root frame, gx,gy,gz (default 0,0,-9.80665): with "
                    "--sensor below movable joints whose columns the file has");
    if (filter)
      sub->add_option("--cutoff", motion.cutoff,
                      "Motion log without JOINT_vel/_acc: zero-phase low-pass cutoff, Hz, for the "
                      "derivatives and the wrench alike (default: min(10, rate/20))")
          ->check(CLI::PositiveNumber);
  };

  auto add_sensor = [&](CLI::App* sub) {
    sub->add_option("--sensor", common.sensor, "Sensor link (default: the URDF root link)");
  };

  CLI::App* model = app.add_subcommand("model", "Measured bodies, joints and base parameters");
  model->add_option("robot", common.urdf, "Robot URDF")->required();
  add_sensor(model);
  model->add_flag("--offset", offset, "Include the six sensor offsets as unknowns");
  model->add_option("--fixed", common.fixed,
                    "Joint held still: JOINT=VALUE (rad or m); repeatable");
  model->add_flag("--json", as_json, "Print JSON (the params file's base_parameters, no values)");
  add_motion(model, false);
  model
      ->add_option("--gravity", motion.gravity,
                   "With --dynamic: 'varying' (a tilting platform; default) or 'level' (the "
                   "same gravity in every sample, along --root-gravity)")
      ->check(CLI::IsMember({"level", "varying"}));
  model->add_flag("--moving-sensor", motion.sensor_moving,
                  "With --dynamic: the sensor frame itself moves (platform, upstream joints)");

  CLI::App* simulate =
      app.add_subcommand("simulate", "Wrenches the URDF's inertials would produce");
  simulate->add_option("robot", common.urdf, "Robot URDF")->required();
  simulate->add_option("plan", plan, "Plan CSV (joint columns, gx,gy,gz)")->required();
  simulate->add_option("-o,--output", out, "Data CSV to write")->required();
  add_sensor(simulate);
  simulate->add_option("--noise-force", sim.noise_force, "Force noise sigma, N")
      ->check(sign_check(false));
  simulate->add_option("--noise-moment", sim.noise_moment, "Moment noise sigma, N m")
      ->check(sign_check(false));
  simulate->add_option("--offset", offset_text, "Constant sensor offset fx,fy,fz,mx,my,mz");
  simulate->add_option("--seed", sim.seed, "Noise seed");
  simulate
      ->add_option("--repeat", sim.repeat,
                   "Samples per plan row, each with its own noise (a log taken while the "
                   "pose is held; default 1)")
      ->check(CLI::Range(1, 1000000));
  add_motion(simulate, false);
  simulate->add_flag("--no-checks", no_checks,
                     "Skip the plan's checks (joints in degrees or mm, gravity units, columns)");

  CLI::App* ident = app.add_subcommand("identify", "Estimate the base parameters from a data CSV");
  ident->add_option("robot", common.urdf, "Robot URDF")->required();
  ident->add_option("data", data, "Data CSV (joints, wrench, optionally gx,gy,gz)")->required();
  ident->add_option("-o,--output", out, "Params JSON to write")->required();
  add_sensor(ident);
  ident->add_flag("--offset", offset, "Estimate the six sensor offsets too");
  ident->add_option("--fixed", common.fixed,
                    "Joint held still in the experiment: JOINT=VALUE (rad or m); repeatable");
  ident->add_flag("--robust", idopts.robust,
                  "Find samples with implausible residuals (a bump, a cable), reject them and "
                  "say which");
  ident
      ->add_option("--drift", drift_text,
                   "Sensor offset drifting: 'linear' in time (column t) or 'per-block' "
                   "(column block: re-zeroed between blocks); implies --offset")
      ->check(CLI::IsMember({"linear", "per-block"}));
  ident
      ->add_option("--rest", rest_text,
                   "A static log with t recorded while the robot moved from pose to pose: 'auto' "
                   "(default) uses only its rest windows, 'off' every row")
      ->check(CLI::IsMember({"auto", "off"}));
  ident->add_option("--delay", delay_text,
                    "With --dynamic: the lag of the wrench behind the joint stream, s (positive "
                    "when the wrench arrives late), or 'auto' to estimate it (within +-20 ms)");
  ident->add_flag("--no-checks", no_checks,
                  "Skip the set-up checks (wrench sign, frame, units, gravity, columns)");
  ident->add_option("--sigma-force", sigma_force, "Force noise sigma, N (default: from residuals)")
      ->check(sign_check(true));
  ident
      ->add_option("--sigma-moment", sigma_moment,
                   "Moment noise sigma, N m (default: from residuals)")
      ->check(sign_check(true));

  ident->add_flag("--physical", physical,
                  "Also fit physically consistent standard parameters (ten per link: mass > 0, "
                  "positive semi-definite pseudo-inertia) that reproduce the base parameters, the "
                  "URDF's inertials where the data cannot see; written under \"physical\"");
  ident->add_option("--urdf-out", urdf_out,
                    "Also write the URDF with the identified inertials (implies --physical; "
                    "everything but the measured links' <inertial> elements kept byte for byte)");
  ident->add_option("--report", report,
                    "Also write an HTML report (plots; needs Python with matplotlib)");
  add_motion(ident, true);

  CLI::App* pred = app.add_subcommand("predict", "Gravity wrench predicted at every row of a CSV");
  pred->add_option("robot", common.urdf, "Robot URDF")->required();
  pred->add_option("params", params, "Params JSON from identify")->required();
  pred->add_option("data", data, "Plan or data CSV")->required();
  pred->add_option("-o,--output", out, "CSV to write: input plus *_pred (and *_comp)");
  pred->add_option("--report", report,
                   "Also write an HTML report (plots; needs Python with matplotlib)");
  pred->add_option("--root-gravity", motion.root_gravity,
                   "Gravity in the URDF root frame, gx,gy,gz (sensor below movable joints)");
  pred->add_option("--cutoff", motion.cutoff,
                   "Dynamic params, log without JOINT_vel/_acc: low-pass cutoff, Hz")
      ->check(CLI::PositiveNumber);
  pred->add_flag("--physical", physical,
                 "Predict from the params file's physical parameters (identify --physical) "
                 "instead of its base parameters");
  pred->add_flag("--no-checks", no_checks,
                 "Skip the file's set-up checks (joint and wrench units, signs, frame, columns)");

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
    if (*model) return run_model(common, offset, as_json, motion);
    if (*simulate) {
      if (!offset_text.empty())
        sim.offset = parse_numbers<6>(offset_text, "--offset", "fx,fy,fz,mx,my,mz");
      sim.dynamic = motion.dynamic;
      return run_simulate(common, plan, out, sim, motion, !no_checks);
    }
    if (*ident) {
      if (ident->count("--sigma-force")) idopts.sigma_force = sigma_force;
      if (ident->count("--sigma-moment")) idopts.sigma_moment = sigma_moment;
      if (!drift_text.empty()) idopts.drift = parse_drift(drift_text);
      if (rest_text == "off") idopts.rest.detection = RestDetection::Off;
      if (delay_text == "auto")
        idopts.delay_auto = true;
      else if (!delay_text.empty())
        idopts.delay = parse_number(delay_text, "--delay");
      if (!motion.dynamic && ident->count("--delay"))
        throw InputError(
            "--delay goes with --dynamic (a motion log): at rest a lag does not matter");
      if (physical || !urdf_out.empty()) idopts.physical = PhysicalOptions{};
      if (motion.dynamic && ident->count("--rest"))
        throw InputError("--rest goes with static identification (--dynamic uses every row)");
      return run_identify(common, data, out, offset, idopts, !no_checks, report, motion, urdf_out);
    }
    if (*pred)
      return run_predict(common.urdf, params, data, out, report, motion, !no_checks, physical);
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

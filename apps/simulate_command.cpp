#include "simulate_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>

#include "hints.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "options.hpp"

namespace massid::cli {

namespace {

int run_simulate(const SimulateCommand& c, const std::string& plan_path, const std::string& out,
                 const SimulateOptions& opts, const MotionFlags& motion, bool checks) {
  const CsvTable table = read_csv(plan_path);
  SampleOptions read = motion.data().samples;
  read.columns = parse_columns(c.columns);
  read.sensor_motion = opts.dynamic;  // at rest, a partial wx..az is ignored (with a note)
  // Joints below the sensor that the plan lacks (a hand's fingers): held still, with a note.
  std::optional<Warning> held;
  const Model model = hold_unlogged_joints(
      hold_joints(load_urdf(c.urdf, c.sensor), parse_held(c.fixed)), table.header,
      fmt::format("{}:{}", table.source, table.header_line), read, &held);
  if (held) std::cerr << "massid: note: " << with_hints(held->message, held->hints) << "\n";
  if (!(model.nominal_total_mass() > 0))
    throw InputError(fmt::format(
        "{}: no measured link has a mass (no <inertial> below sensor link '{}'): the simulated "
        "wrench would be zero; add the links' <inertial> elements (mass, origin) to the URDF",
        c.urdf, model.sensor_link()));
  print_column_note(column_note(model, table.header,
                                fmt::format("{}:{}", table.source, table.header_line),
                                WrenchColumns::Optional, read));
  const Samples plan = read_samples(model, table, WrenchColumns::Optional, read);
  if (plan.gravity_from_force) throw InputError(plan_path + ": simulate needs gx,gy,gz columns");
  // Joints in degrees or mm, gravity in g, ... (a wrench in the plan is replaced: not judged).
  Samples judged = plan;
  judged.wrench.resize(0, 0);
  if (checks && !check_input(model, judged, column_roles(model, table.header, read), opts.dynamic))
    return 2;
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

}  // namespace

void add_simulate_command(CLI::App& app, SimulateCommand& c) {
  c.app = app.add_subcommand("simulate", "Wrenches the URDF's inertials would produce");
  CLI::App* simulate = c.app;
  simulate->add_option("robot", c.urdf, "Robot URDF")->required();
  simulate->add_option("plan", c.plan, "Plan CSV (joint columns, gx,gy,gz)")->required();
  simulate->add_option("-o,--output", c.output, "Data CSV to write")->required();
  simulate->add_option("--sensor", c.sensor, "Sensor link (default: the URDF root link)");
  simulate->add_option("--noise-force", c.sim.noise_force, "Force noise sigma, N")
      ->check(sign_check(false));
  simulate->add_option("--noise-moment", c.sim.noise_moment, "Moment noise sigma, N m")
      ->check(sign_check(false));
  simulate->add_option("--sensor-offset", c.sensor_offset,
                       "Constant sensor offset fx,fy,fz,mx,my,mz");
  simulate->add_option("--offset", c.old_offset,
                       "Deprecated spelling of --sensor-offset fx,fy,fz,mx,my,mz");
  simulate->add_option("--seed", c.sim.seed, "Noise seed");
  simulate->add_option("--fixed", c.fixed,
                       "Joint held still: JOINT=VALUE (rad or m; its column, if any, is not "
                       "read); repeatable");
  simulate
      ->add_option("--repeat", c.sim.repeat,
                   "Samples per plan row, each with its own noise (a log taken while the "
                   "pose is held; default 1)")
      ->check(CLI::Range(1, 1000000));
  add_motion_options(simulate, c.motion, false);
  add_level_gravity_option(simulate, c.motion.level_gravity);
  simulate->add_flag("--no-checks", c.no_checks,
                     "Skip the plan's checks (joints in degrees or mm, gravity units, columns)");
  add_columns_option(simulate, c.columns);
}

int run_simulate(SimulateCommand c) {
  if (c.app->count("--offset")) {
    if (c.app->count("--sensor-offset"))
      throw InputError("--offset is the old spelling of --sensor-offset: give one");
    c.sim.offset = parse_numbers<6>(c.old_offset, "--offset", "fx,fy,fz,mx,my,mz");
    std::cerr << "massid: warning: --offset with six numbers is deprecated: use "
                 "--sensor-offset\n";
  }
  if (!c.sensor_offset.empty())
    c.sim.offset = parse_numbers<6>(c.sensor_offset, "--sensor-offset", "fx,fy,fz,mx,my,mz");
  c.sim.dynamic = c.motion.dynamic;
  return run_simulate(c, c.plan, c.output, c.sim, c.motion, !c.no_checks);
}

}  // namespace massid::cli

#include "identify_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>

#include "hints.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/identify/physical.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/identify/urdf_inertials.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/report/report.hpp"
#include "options.hpp"
#include "python_report.hpp"

namespace massid::cli {

// The physical fit did not converge (docs/cli.md's exit codes).
constexpr int kExitNotConverged = 4;

void add_identify_command(CLI::App& app, IdentifyCommand& c) {
  c.app = app.add_subcommand("identify", "Estimate the base parameters from a data CSV");
  CLI::App* i = c.app;
  i->add_option("robot", c.urdf, "Robot URDF")->required();
  i->add_option("data", c.data, "Data CSV (joints, wrench, optionally gx,gy,gz)")->required();
  i->add_option("-o,--output", c.output, "Params JSON to write")->required();
  i->add_option("--sensor", c.sensor, "Sensor link (default: the URDF root link)");
  i->add_flag("--offset", c.offset, "Estimate the six sensor offsets too");
  i->add_option("--fixed", c.fixed,
                "Joint held still in the experiment: JOINT=VALUE (rad or m); repeatable");
  i->add_flag("--robust", c.robust,
              "Find samples with implausible residuals (a bump, a cable), reject them and "
              "say which");
  i->add_option("--drift", c.drift,
                "Sensor offset drifting: 'linear' in time (column t) or 'per-block' "
                "(column block: re-zeroed between blocks); implies --offset");
  i->add_option("--rest", c.rest,
                "A static log with t recorded while the robot moved from pose to pose: 'auto' "
                "(default) uses only its rest windows, 'off' every row");
  i->add_option("--delay", c.delay,
                "With --dynamic: the lag of the wrench behind the joint stream, s (positive "
                "when the wrench arrives late), or 'auto' to estimate it (within +-20 ms)");
  i->add_flag("--no-checks", c.no_checks,
              "Skip the set-up checks (wrench sign, frame, units, gravity, columns)");
  i->add_option("--sigma-force", c.sigma_force, "Force noise sigma, N (default: from residuals)")
      ->check(sign_check(true));
  i->add_option("--sigma-moment", c.sigma_moment,
                "Moment noise sigma, N m (default: from residuals)")
      ->check(sign_check(true));
  i->add_flag("--physical", c.physical,
              "Also fit physically consistent standard parameters (ten per link: mass > 0, "
              "positive semi-definite pseudo-inertia) that reproduce the base parameters, the "
              "URDF's inertials where the data cannot see; written under \"physical\"");
  i->add_option("--urdf-out", c.urdf_out,
                "Also write the URDF with the identified inertials (implies --physical; "
                "everything but the measured links' <inertial> elements kept byte for byte)");
  i->add_option("--physical-iterations", c.physical_iterations,
                "The physical fit's solver limit (default 500; implies --physical)")
      ->check(CLI::PositiveNumber);
  i->add_flag("--accept-unconverged", c.accept_unconverged,
              "Write --urdf-out and exit 0 even when the physical fit did not converge (with a "
              "warning; without: exit 4 and no URDF)");
  i->add_option("--report", c.report,
                "Also write an HTML report (plots; needs Python with matplotlib)");
  i->add_flag("--dynamic", c.dynamic,
              "Motion: the full wrench (weight and motion) over ten parameters per link");
  i->add_option("--root-gravity", c.root_gravity,
                "Gravity in the URDF root frame, gx,gy,gz (default 0,0,-9.80665): with "
                "--sensor below movable joints whose columns the file has");
  add_level_gravity_option(i, c.level_gravity);
  i->add_option("--cutoff", c.cutoff,
                "Motion log without JOINT_vel/_acc: zero-phase low-pass cutoff, Hz, for the "
                "derivatives and the wrench alike (default: min(10, rate/20))")
      ->check(CLI::PositiveNumber);
  add_columns_option(i, c.columns);
}

IdentifyRequest IdentifyCommand::request() const {
  IdentifyRequest r;
  r.sensor_link = sensor;
  r.held = parse_held(fixed);
  r.offset = offset;
  r.dynamic = dynamic;
  r.drift = drift;
  r.rest = rest;
  r.delay = delay;
  if (app->count("--cutoff")) r.cutoff = cutoff;
  r.checks = !no_checks;
  r.robust = robust;
  r.physical = physical || !urdf_out.empty() || physical_iterations > 0;
  r.physical_iterations = physical_iterations;
  if (app->count("--sigma-force")) r.sigma_force = sigma_force;
  if (app->count("--sigma-moment")) r.sigma_moment = sigma_moment;
  if (!root_gravity.empty())
    r.root_gravity = parse_numbers<3>(root_gravity, "--root-gravity", "gx,gy,gz");
  r.level_gravity = parse_level_gravity(level_gravity);
  // With --report the samples and fitted wrenches are kept for the report,
  // which draws this fit (identification.hpp); without, any log in constant memory.
  r.keep_samples = !report.empty();
  r.columns = parse_columns(columns);
  return r;
}

int run_identify(const IdentifyCommand& c) {
  const IdentifyRequest request = c.request();
  request.validate(spelling());                 // every rule, before any work
  if (!c.report.empty()) check_report_tools();  // before any work
  // Joints below the sensor that the log lacks (a hand's fingers) are held still, with a note.
  std::optional<Warning> held;
  Model model = hold_unlogged_file_joints(request.load_model(c.urdf), c.data,
                                          request.sample_options(), &held);
  if (held) std::cerr << "massid: note: " << with_hints(held->message, held->hints) << "\n";
  // Which columns are read under other names, which are ignored (before any finding on them).
  print_column_note(file_column_note(model, c.data, request.sample_options()));
  // Before any work: wrong signs, units, frames or columns (the first 20 000
  // rows of a big file). A joint that never moves is left to the
  // identifiability diagnosis below, which names it with the fix.
  SetupCheckOptions sopts;
  sopts.constant_joints = false;
  sopts.motion = request.dynamic;
  sopts.read = request.sample_options();  // the root gravity
  if (!c.no_checks && !report_setup(check_setup_file(model, c.data, sopts))) return 2;
  const Identification ident = identify(std::move(model), request, IdentifySource::file(c.data));
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
              << with_hints(ident.warnings[i].message, ident.warnings[i].hints) << "\n";
  write_file_atomically(c.output, params_json(ident.model, ident.base, &summary,
                                              ident.physical ? &*ident.physical : nullptr));
  std::cout << identify_report(ident.model, ident.base, summary, c.data);
  if (ident.physical) std::cout << physical_report(ident.base, *ident.physical, spell);
  std::cout << "wrote " << c.output << "\n";
  // A physical fit that did not converge: said, and no URDF from it unless accepted.
  const bool unconverged = ident.physical && !ident.physical->converged;
  if (unconverged)
    std::cerr << fmt::format(
        "massid: warning: the physical fit did not converge ({} iterations: {}): its bodies are "
        "written under \"physical\" with \"converged\": false{}; raise the limit with "
        "--physical-iterations N{}\n",
        ident.physical->iterations, ident.physical->message,
        c.urdf_out.empty()     ? ""
        : c.accept_unconverged ? fmt::format(", and to {} (--accept-unconverged)", c.urdf_out)
                               : fmt::format(", {} is not written", c.urdf_out),
        c.accept_unconverged ? "" : ", or accept them with --accept-unconverged (exit 0)");
  if (!c.urdf_out.empty() && (!unconverged || c.accept_unconverged)) {
    const bool rest = ident.physical->static_layout;
    write_file_atomically(
        c.urdf_out,
        identified_urdf(ident.model, *ident.physical,
                        fmt::format("identified by massid from {}: {}", c.data,
                                    rest ? "mass and centre of mass at rest, the inertia about "
                                           "the centre of mass the URDF's"
                                         : "mass, centre of mass and inertia in motion")));
    std::cout << fmt::format(
        "wrote {}: {} with the physical inertials of the measured links ({}), every other byte "
        "as it was\n",
        c.urdf_out, c.urdf,
        rest ? "masses and centres of mass" : "masses, centres of mass, inertias");
  }
  const int code = unconverged && !c.accept_unconverged ? kExitNotConverged : 0;
  if (!c.report.empty()) {
    const int report = run_identify_report(ident, c.report);
    return report != 0 ? report : code;
  }
  return code;
}

}  // namespace massid::cli

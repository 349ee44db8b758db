#include "design_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>

#include "hints.hpp"
#include "massid/core/errors.hpp"
#include "massid/design/design.hpp"
#include "massid/design/excitation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"
#include "options.hpp"

namespace massid::cli {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

void add_design_command(CLI::App& app, DesignCommand& c) {
  c.app = app.add_subcommand("design", "Plan the poses that determine every base parameter best");
  CLI::App* d = c.app;
  d->add_option("robot", c.urdf, "Robot URDF")->required();
  d->add_option("-o,--output", c.output, "Plan CSV to write");
  d->add_option("--poses", c.poses, "Number of poses")->check(CLI::Range(1, 100000));
  d->add_option("--sensor", c.sensor, "Sensor link (default: the URDF root link)");
  auto* tmax = d->add_option("--tilt-max", c.tilt_max_deg, "Any platform tilt up to DEG from level")
                   ->check(CLI::Range(0.0, 89.0));
  auto* tl =
      d->add_option("--tilts", c.tilts, "Only these tilts: ax_deg:ay_deg,... (about x, then y)");
  tmax->excludes(tl);
  d->add_option("--tilt-groups", c.tilt_groups,
                "With --tilt-max: use this many tilts, chosen by the optimiser (default 4; 0: a "
                "tilt per pose)")
      ->check(CLI::Range(0, 1000))
      ->needs(tmax);
  d->add_option("--gravity", c.gravity,
                "Gravity gx,gy,gz in the sensor frame when level (default 0,0,-9.80665)");
  d->add_option("--fixed", c.fixed, "Hold a joint: JOINT=VALUE (rad or m); repeatable");
  d->add_option("--limits", c.limits, "Narrow a joint's range: JOINT=LO:HI; repeatable");
  d->add_option("--min-height", c.min_height,
                "Every moving link origin, centre of mass and primitive collision shape at least "
                "H m above the platform plane (through the sensor origin, normal to level "
                "gravity; with --dynamic and a sensor below movable joints: the floor, through "
                "the URDF root's origin normal to --root-gravity); default 0.05; 'none': no "
                "constraint");
  d->add_option("--self-clearance", c.self_clearance,
                "With --dynamic and a sensor below movable joints: the arm's links that no single "
                "link joins keep their centre lines D m apart (default 0.05; 'none': not "
                "checked)");
  d->add_option("--root-gravity", c.root_gravity,
                "With --dynamic and a sensor below movable joints: gravity in the URDF root "
                "frame, gx,gy,gz (default 0,0,-9.80665)");
  d->add_option("--level-poses", c.level_poses,
                "Poses kept level when tilts are allowed (default: a quarter of them; 0: the "
                "optimiser chooses every tilt)")
      ->check(CLI::Range(0, 100000));
  d->add_option("--criterion", c.criterion, "cond (paper eq. 36, default) or d-opt")
      ->check(CLI::IsMember({"cond", "d-opt"}));
  d->add_option("--noise-force", c.noise_force,
                "Force noise sigma for the predictions, N (default 0.05)")
      ->check(sign_check(true));
  d->add_option("--noise-moment", c.noise_moment,
                "Moment noise sigma for the predictions, N m (default 0.005)")
      ->check(sign_check(true));
  d->add_flag("--offset", c.offset, "The six sensor offsets are estimated too");
  d->add_option("--seed", c.seed, "Random seed (same seed, same plan)");
  d->add_option("--candidates", c.candidates, "Random candidate poses (default: automatic)")
      ->check(CLI::Range(10, 1000000));
  d->add_option("--evaluate", c.evaluate,
                "Print the figures of an existing plan or data file instead");
  d->add_flag("--no-checks", c.no_checks,
              "With --evaluate: skip the file's checks (joints in degrees or mm, units, columns)");
  add_columns_option(d, c.columns);
  d->add_flag("--dynamic", c.dynamic,
              "An exciting trajectory for identification in motion (finite Fourier series, at "
              "rest at both ends) instead of static poses");
  d->add_option("--duration", c.duration, "With --dynamic: length, s (default 30)")
      ->check(CLI::PositiveNumber);
  d->add_option("--rate", c.rate, "With --dynamic: samples per second written (default 1000)")
      ->check(CLI::PositiveNumber);
  d->add_option("--period", c.period, "With --dynamic: Fourier period, s (default 10)")
      ->check(CLI::PositiveNumber);
  d->add_option("--harmonics", c.harmonics, "With --dynamic: harmonics per joint (default 5)")
      ->check(CLI::Range(1, 50));
  d->add_option("--velocity-limit", c.velocity_limits,
                "With --dynamic: JOINT=V (rad/s or m/s; default the URDF's, else 1); repeatable");
  d->add_option("--evaluations", c.evaluations,
                "With --dynamic: criterion evaluations of the optimiser (default 6000; 0: the best "
                "of the random starts)")
      ->check(CLI::Range(0, 100000000));
  d->add_option("--acceleration-limit", c.acceleration_limits,
                "With --dynamic: JOINT=A (rad/s^2 or m/s^2; default 4); repeatable");
}

namespace {

// OPTION H (m), or none/off: no constraint; absent: the default.
std::optional<double> parse_distance(const DesignCommand& c, const char* option,
                                     const std::string& text, double default_value) {
  if (!c.app->count(option)) return default_value;
  if (text == "none" || text == "off") return std::nullopt;
  const double h = parse_number(text, option);
  if (!std::isfinite(h))
    throw InputError(fmt::format("{}: '{}' should be a distance in m or 'none'", option, text));
  return h;
}

std::optional<double> parse_min_height(const DesignCommand& c) {
  return parse_distance(c, "--min-height", c.min_height, kDefaultMinHeight);
}

// --tilts ax_deg:ay_deg,... -> tilts (rad); empty text: none.
std::vector<Tilt> parse_tilts(const std::string& text) {
  std::vector<Tilt> tilts;
  if (text.empty()) return tilts;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    const size_t colon = item.find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("--tilts: '{}' should read ax_deg:ay_deg", item));
    tilts.push_back({parse_number(item.substr(0, colon), "--tilts") * kDeg,
                     parse_number(item.substr(colon + 1), "--tilts") * kDeg});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return tilts;
}

int run_design_dynamic(const DesignCommand& c, Model model, const BaseParameterOptions& bo_in,
                       bool move_arm) {
  if (c.output.empty()) throw InputError("design --dynamic: -o TRAJ.csv is required");
  for (const char* opt : {"--poses", "--evaluate", "--level-poses", "--no-checks", "--columns"})
    if (c.app->count(opt))
      throw InputError(fmt::format(
          "design --dynamic: {} applies to static plans only (a trajectory has no poses to count "
          "or keep level; check a trajectory by simulating and identifying it)",
          opt));
  // A wrist (a sensor below movable joints): the trajectory moves the arm's
  // joints too; they take --limits, --velocity-limit, --acceleration-limit.
  const bool wrist = move_arm;
  // The joint named `name` of the trajectory (trajectory_joints order), and its index there.
  const auto find = [&](const std::string& name, const char* option) -> std::pair<Joint*, int> {
    const int nu = wrist ? model.num_upstream_joints() : 0;
    for (int u = 0; u < nu; ++u)
      if (model.upstream_joints[u].name == name) return {&model.upstream_joints[u], u};
    const int j = model.find_joint(name);
    if (j < 0) throw InputError(fmt::format("{}: no movable joint '{}'", option, name));
    return {&model.joints[j], nu + j};
  };
  for (const std::string& l : c.limits) {  // narrow a joint's range
    const auto [joint, range] = parse_assignment(l, "--limits");
    const size_t colon = range.find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("--limits: '{}' should read JOINT=LO:HI", l));
    Joint& jt = *find(joint, "--limits").first;
    const double lo = parse_number(range.substr(0, colon), "--limits " + joint),
                 hi = parse_number(range.substr(colon + 1), "--limits " + joint);
    if (!(lo < hi))
      throw InputError(fmt::format("--limits {}: empty range [{}, {}]", joint, lo, hi));
    jt.lower = jt.limited ? std::max(lo, jt.lower) : lo;
    jt.upper = jt.limited ? std::min(hi, jt.upper) : hi;
    jt.limited = true;
  }
  ExcitationOptions o;
  o.harmonics = c.harmonics;
  o.period = c.period;
  o.duration = c.duration;
  // At rest at both ends: the trajectory is at rest at every whole period, so
  // the period becomes the nearest that divides the duration evenly.
  std::string period_note;
  if (o.period > 0 && o.duration > 0) {
    const double periods = std::max(1.0, std::round(o.duration / o.period));
    if (std::abs(periods * o.period - o.duration) > 1e-9 * o.duration) {
      period_note = fmt::format(
          " (--period {:.6g} s adjusted to {:.6g} period{} in {:.6g} s: at rest at both ends)",
          o.period, periods, periods > 1 ? "s" : "", o.duration);
      o.period = o.duration / periods;
    }
  }
  o.rate = c.rate;
  o.seed = c.seed;
  if (c.candidates > 0) o.candidates = c.candidates;
  if (c.app->count("--evaluations")) o.evaluations = c.evaluations;
  o.criterion = c.criterion == "d-opt" ? Criterion::DOpt : Criterion::Cond;
  o.noise_force = c.noise_force;
  o.noise_moment = c.noise_moment;
  if (!c.gravity.empty()) o.level_gravity = parse_numbers<3>(c.gravity, "--gravity", "gx,gy,gz");
  o.tilts = parse_tilts(c.tilts);
  if (c.app->count("--tilt-max")) {
    if (c.tilt_groups < 1)
      throw InputError(
          "design --dynamic --tilt-max: --tilt-groups must be at least 1 (the trajectory runs "
          "once per tilt)");
    o.tilts = cone_tilts(o.level_gravity, c.tilt_max_deg * kDeg, c.tilt_groups);
  }
  o.min_height = parse_min_height(c);
  o.min_height_required = c.app->count("--min-height") > 0;
  o.self_clearance = parse_distance(c, "--self-clearance", c.self_clearance, kDefaultSelfClearance);
  if (!c.root_gravity.empty())
    o.root_gravity = parse_numbers<3>(c.root_gravity, "--root-gravity", "gx,gy,gz");
  for (const std::string& v : c.velocity_limits) {
    const auto [joint, value] = parse_assignment(v, "--velocity-limit");
    find(joint, "--velocity-limit").first->velocity_limit =
        parse_number(value, "--velocity-limit " + joint);
  }
  o.move_arm = wrist;
  o.limits.joint_acceleration.assign((wrist ? model.num_upstream_joints() : 0) + model.num_joints(),
                                     0.0);
  for (const std::string& v : c.acceleration_limits) {
    const auto [joint, value] = parse_assignment(v, "--acceleration-limit");
    o.limits.joint_acceleration[find(joint, "--acceleration-limit").second] =
        parse_number(value, "--acceleration-limit " + joint);
  }
  // The base parameters of the data the trajectory gives: gravity fixed
  // unless the blocks' gravities differ (tilts) or the arm turns the sensor.
  const std::vector<Eigen::Vector3d> gravities = block_gravities(o);
  BaseParameterOptions bo = bo_in;
  bo.layout = ParameterLayout::full();
  bo.fixed_gravity = !wrist;
  for (const Eigen::Vector3d& g : gravities)
    bo.fixed_gravity = bo.fixed_gravity && (g - gravities[0]).norm() <= 1e-6 * g.norm();
  bo.sensor_gravity = gravities[0];
  bo.sensor_moving = wrist;
  const BaseParameters base = find_base_parameters(model, bo);
  const ExcitationSummary s = design_excitation(model, base, o);
  if (!s.identifiable) throw IdentifiabilityError(s.identifiability_message);
  write_trajectory(c.output, model, s.samples);

  const bool cond = o.criterion == Criterion::Cond;
  if (wrist) {
    std::vector<std::string> names;
    for (const Joint& j : model.upstream_joints) names.push_back(j.name);
    std::cout << fmt::format(
        "sensor link '{}' below movable joints: the trajectory moves the arm ({}){}; gravity "
        "from them and the root gravity {:g},{:g},{:g}\n",
        model.sensor_link(), fmt::join(names, ", "),
        model.num_joints() > 0 ? " and the joints below the sensor" : "", o.root_gravity.x(),
        o.root_gravity.y(), o.root_gravity.z());
  }
  std::cout << fmt::format(
      "exciting trajectory for {} (sensor link '{}'): {} harmonics, period {:.6g} s, {:.6g} s at "
      "{:.6g} Hz{}{}; criterion {} optimised over the Fourier coefficients in {} evaluations on a "
      "{:.3g} Hz grid, {:.3g} s (seed {})\n",
      model.name, model.sensor_link(), o.harmonics, o.period, o.duration, o.rate, period_note,
      gravities.size() > 1 ? fmt::format(", once per tilt ({} blocks)", gravities.size()) : "",
      cond ? "cond" : "d-opt", s.evaluations, s.grid_rate, s.seconds, o.seed);
  for (size_t b = 0; b < o.tilts.size(); ++b)
    std::cout << fmt::format(
        "  block {}: tilt {:.4g}:{:.4g} deg (about x, then y), gravity {:.4g},{:.4g},{:.4g}\n", b,
        o.tilts[b].x / kDeg, o.tilts[b].y / kDeg, gravities[b].x(), gravities[b].y(),
        gravities[b].z());
  std::cout << fmt::format(
      "limits at every written sample: positions within the joints' limits ({:g} % margin), "
      "velocities (URDF <limit velocity>, else {:g}, or --velocity-limit), accelerations "
      "(--acceleration-limit, default {:g}); at rest (velocity and acceleration 0) at t = 0{}\n",
      100 * o.limits.position_margin, o.limits.default_velocity, o.limits.acceleration,
      s.at_rest_at_end ? " and at the end of each block"
                       : " only (the duration is not a whole number of periods: the end is not "
                         "at rest)");
  if (wrist) {
    std::cout << (o.min_height ? fmt::format("clearance: the arm's moving link origins and the "
                                             "tool at least {:g} m above the floor (the plane "
                                             "through the URDF root's origin normal to the root "
                                             "gravity); lowest {:.3g} m ({})",
                                             *o.min_height, s.lowest_clearance, s.lowest_link)
                               : std::string("clearance above the floor: not constrained "
                                             "(--min-height none)"));
    std::cout << (o.self_clearance
                      ? fmt::format("; the arm's links {:g} m apart (centre lines of links no "
                                    "single link joins); least {:.3g} m ({})\n",
                                    *o.self_clearance, s.lowest_self_clearance, s.self_pair)
                      : std::string("; self-clearance not checked (--self-clearance none)\n"));
  } else if (s.min_height_relaxed)
    std::cout << fmt::format(
        "clearance: not constrained (no pose keeps every moving point {:g} m above the platform "
        "plane: the default --min-height is dropped; give one to insist)\n",
        *o.min_height);
  else if (o.min_height)
    std::cout << fmt::format(
        "clearance: every moving link origin, centre of mass and collision sphere at least {:g} "
        "m above the platform plane; lowest {:.3g} m ('{}'); --min-height none turns it off\n",
        *o.min_height, s.lowest_clearance, s.lowest_link);
  else
    std::cout << "clearance: not constrained (--min-height none)\n";
  if (cond && s.random_count > 0)
    std::cout << fmt::format(
        "condition number {:.4g}, random trajectories within the same limits: median {:.4g} "
        "({} seeds, {:.3g}x better; both on the criterion's grid, the optimised {:.4g})\n",
        s.condition_number, s.random_median, s.random_count, s.random_median / s.grid_figure,
        s.grid_figure);
  else if (s.random_count > 0)
    std::cout << fmt::format(
        "log det of the information matrix on the criterion's grid {:.6g}, random trajectories "
        "within the same limits: median {:.6g} ({} seeds, +{:.4g}); over the written samples "
        "{:.6g}\n",
        s.grid_figure, s.random_median, s.random_count, s.grid_figure - s.random_median, s.log_det);
  if (s.tool_parameters > 0)
    std::cout << fmt::format(
        "condition number of the tool's {} parameters{} (the links below the sensor as one rigid "
        "body, their joints at the trajectory's centre): {:.4g}\n",
        s.tool_parameters - (base.offset ? 6 : 0), base.offset ? " and the offsets" : "",
        s.tool_condition_number);
  std::cout << fmt::format(
      "condition number{} (all rows, columns scaled, noise-weighted): {:.4g}\n"
      "predicted std at {} N / {} N m noise, {} dynamic base parameters{}:\n",
      !wrist                  ? ""
      : s.tool_parameters > 0 ? " of all the identified parameters"
                              : " of the tool's parameters",
      s.condition_number, o.noise_force, o.noise_moment, base.num_mass(),
      base.offset ? " and the offsets" : "");
  for (int i = 0; i < base.num_unknowns(); ++i) {
    const bool mass = i < base.num_mass();
    std::cout << fmt::format("  {:<10} {:>10.2g} {:<6} {}\n", base.unknown_name(i),
                             s.predicted_std[i],
                             mass ? base.params[i].unit : (i - base.num_mass() < 3 ? "N" : "N m"),
                             mass ? base.params[i].expression : "sensor offset");
  }
  std::cout << "wrote " << c.output << "\n";
  return 0;
}

}  // namespace

int run_design(const DesignCommand& c) {
  const Model urdf = load_urdf(c.urdf, c.sensor);
  const auto held = parse_held(c.fixed);
  for (const auto& [name, value] : held)  // a held joint stays within its URDF limits too
    if (const int j = urdf.find_joint(name);
        j >= 0 && urdf.joints[j].limited &&
        !(value >= urdf.joints[j].lower && value <= urdf.joints[j].upper))
      throw InputError(fmt::format("--fixed {}={}: outside the URDF limits [{}, {}]", name, value,
                                   urdf.joints[j].lower, urdf.joints[j].upper));
  Model model = hold_joints(urdf, held);
  // A plan to evaluate without columns for some joints below the sensor: they are held, with a
  // note.
  std::optional<CsvTable> evaluated;
  SampleOptions read;
  read.columns = parse_columns(c.columns);
  read.sensor_motion = false;  // static poses: a partial wx..az is ignored (with a note)
  if (!c.evaluate.empty()) {
    evaluated = read_csv(c.evaluate);
    std::optional<Warning> note;
    model = hold_unlogged_joints(std::move(model), evaluated->header,
                                 fmt::format("{}:{}", evaluated->source, evaluated->header_line),
                                 read, &note);
    if (note) std::cerr << "massid: note: " << with_hints(note->message, note->hints) << "\n";
  }
  BaseParameterOptions bo;
  bo.offset = c.offset;
  // A sensor below movable joints (a wrist): the plan moves the arm, gravity
  // from it and --root-gravity, unless gravity in the sensor frame is given
  // (--gravity, --tilts, --tilt-max): the arm then stays wherever it is.
  const bool sensor_frame_gravity =
      c.app->count("--gravity") || c.app->count("--tilts") || c.app->count("--tilt-max");
  const bool move_arm = model.num_upstream_joints() > 0 && !sensor_frame_gravity;
  if (!move_arm)
    for (const char* opt : {"--self-clearance", "--root-gravity"})
      if (c.app->count(opt))
        throw InputError(
            model.num_upstream_joints() == 0
                ? fmt::format("design: {} applies to a sensor below movable joints (a wrist); "
                              "sensor link '{}' is the root of the moving joints",
                              opt, model.sensor_link())
                : fmt::format("design: {} goes with the arm's motion above sensor link '{}', "
                              "which --gravity, --tilts and --tilt-max hold still (gravity "
                              "given in the sensor frame): give one or the other",
                              opt, model.sensor_link()));
  if (c.dynamic) return run_design_dynamic(c, model, bo, move_arm);
  const BaseParameters base = find_base_parameters(model, bo);

  DesignOptions o;
  o.poses = c.poses;
  o.criterion = c.criterion == "d-opt" ? Criterion::DOpt : Criterion::Cond;
  o.noise_force = c.noise_force;
  o.noise_moment = c.noise_moment;
  o.seed = c.seed;
  o.candidates = c.candidates;
  if (c.app->count("--tilt-max")) o.tilt_max = c.tilt_max_deg * kDeg;
  o.tilt_groups = c.tilt_groups;
  o.tilts = parse_tilts(c.tilts);
  if (!c.gravity.empty()) o.level_gravity = parse_numbers<3>(c.gravity, "--gravity", "gx,gy,gz");
  for (const std::string& l : c.limits) {
    const auto [joint, range] = parse_assignment(l, "--limits");
    const size_t colon = range.find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("--limits: '{}' should read JOINT=LO:HI", l));
    o.limits[joint] = {parse_number(range.substr(0, colon), "--limits " + joint),
                       parse_number(range.substr(colon + 1), "--limits " + joint)};
  }
  o.min_height = parse_min_height(c);
  o.min_height_required = c.app->count("--min-height") > 0;
  o.self_clearance = parse_distance(c, "--self-clearance", c.self_clearance, kDefaultSelfClearance);
  if (!c.root_gravity.empty())
    o.root_gravity = parse_numbers<3>(c.root_gravity, "--root-gravity", "gx,gy,gz");
  o.move_arm = move_arm;
  if (c.app->count("--level-poses")) o.level_poses = c.level_poses;

  if (!c.evaluate.empty()) {
    const CsvTable& table = *evaluated;
    // A plan whose gravity comes from its tilt columns alone: they turn
    // design's level gravity (--gravity, default 0,0,-9.80665), as when it
    // wrote them.
    const std::vector<std::string> roles = column_roles(model, table.header, read);
    const auto has = [&](const std::string& n) {
      return std::find(roles.begin(), roles.end(), n) != roles.end();
    };
    const bool upstream =
        std::any_of(model.upstream_joints.begin(), model.upstream_joints.end(),
                    [&](const Joint& j) { return has(j.name) || has(j.name + "_deg"); });
    if (has("tilt_x_deg") && !has("gx") && !upstream) read.level_gravity = o.level_gravity;
    print_column_note(column_note(model, table.header,
                                  fmt::format("{}:{}", table.source, table.header_line),
                                  WrenchColumns::Optional, read));
    const Samples plan = read_samples(model, table, WrenchColumns::Optional, read);
    if (!c.no_checks && !check_input(model, plan, column_roles(model, table.header, read), false))
      return 2;
    const DesignSummary s = evaluate_plan(model, base, plan, o);
    std::cout << design_report(model, base, s, o, c.evaluate, cli::spell);
    if (!s.identifiable) throw IdentifiabilityError(s.identifiability_message);
    return 0;
  }
  if (c.output.empty()) throw InputError("design: -o PLAN.csv is required (or --evaluate FILE)");
  if (c.poses < 1) throw InputError("design: --poses N is required (or --evaluate FILE)");
  const DesignSummary s = design(model, base, o);
  if (!s.identifiable) throw IdentifiabilityError(s.identifiability_message);
  write_plan(c.output, model, s.plan);
  std::cout << design_report(model, base, s, o, "", cli::spell);
  std::cout << "wrote " << c.output << "\n";
  return 0;
}

}  // namespace massid::cli

#include "design_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <numbers>

#include "massid/csv.hpp"
#include "massid/design.hpp"
#include "massid/errors.hpp"
#include "massid/report.hpp"
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
                "Moving link origins at least H m above the platform plane");
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
}

int run_design(const DesignCommand& c) {
  const Model urdf = load_urdf(c.urdf, c.sensor);
  const auto held = parse_held(c.fixed);
  for (const auto& [name, value] : held)  // a held joint stays within its URDF limits too
    if (const int j = urdf.find_joint(name);
        j >= 0 && urdf.joints[j].limited &&
        !(value >= urdf.joints[j].lower && value <= urdf.joints[j].upper))
      throw InputError(fmt::format("--fixed {}={}: outside the URDF limits [{}, {}]", name, value,
                                   urdf.joints[j].lower, urdf.joints[j].upper));
  const Model model = hold_joints(urdf, held);
  BaseParameterOptions bo;
  bo.offset = c.offset;
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
  if (!c.tilts.empty()) {
    size_t start = 0;
    while (start <= c.tilts.size()) {
      const size_t comma = c.tilts.find(',', start);
      const std::string item =
          c.tilts.substr(start, comma == std::string::npos ? comma : comma - start);
      const size_t colon = item.find(':');
      if (colon == std::string::npos)
        throw InputError(fmt::format("--tilts: '{}' should read ax_deg:ay_deg", item));
      o.tilts.push_back({parse_number(item.substr(0, colon), "--tilts") * kDeg,
                         parse_number(item.substr(colon + 1), "--tilts") * kDeg});
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  if (!c.gravity.empty()) o.level_gravity = parse_numbers<3>(c.gravity, "--gravity", "gx,gy,gz");
  for (const std::string& l : c.limits) {
    const auto [joint, range] = parse_assignment(l, "--limits");
    const size_t colon = range.find(':');
    if (colon == std::string::npos)
      throw InputError(fmt::format("--limits: '{}' should read JOINT=LO:HI", l));
    o.limits[joint] = {parse_number(range.substr(0, colon), "--limits " + joint),
                       parse_number(range.substr(colon + 1), "--limits " + joint)};
  }
  if (c.app->count("--min-height")) o.min_height = c.min_height;

  if (!c.evaluate.empty()) {
    const Samples plan = read_samples(model, read_csv(c.evaluate), WrenchColumns::Optional);
    const DesignSummary s = evaluate_plan(model, base, plan, o);
    std::cout << design_report(model, base, s, o, c.evaluate);
    if (!s.identifiable) throw IdentifiabilityError(s.identifiability_message);
    return 0;
  }
  if (c.output.empty()) throw InputError("design: -o PLAN.csv is required (or --evaluate FILE)");
  if (c.poses < 1) throw InputError("design: --poses N is required (or --evaluate FILE)");
  const DesignSummary s = design(model, base, o);
  if (!s.identifiable) throw IdentifiabilityError(s.identifiability_message);
  write_plan(c.output, model, s.plan);
  std::cout << design_report(model, base, s, o, "");
  std::cout << "wrote " << c.output << "\n";
  return 0;
}

}  // namespace massid::cli

#include "model_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"

namespace massid::cli {

namespace {

int run_model(const ModelCommand& c, bool offset, bool as_json, const MotionFlags& motion) {
  const Model model = hold_joints(load_urdf(c.urdf, c.sensor), parse_held(c.fixed));
  BaseParameterOptions opts;
  std::string assumption;  // the sensor frame's motion, said (text output)
  if (motion.dynamic) {
    opts.layout = ParameterLayout::full();
    opts.fixed_gravity = motion.gravity_model == "level";
    // Below movable joints the sensor frame moves with them, as identify in
    // motion counts (their motion excites the measured bodies), unless told it rests.
    const bool below = model.num_upstream_joints() > 0;
    if (motion.sensor_moving && motion.sensor_at_rest)
      throw InputError("--moving-sensor and --sensor-at-rest contradict each other: give one");
    opts.sensor_moving = motion.sensor_moving || (below && !motion.sensor_at_rest);
    if (below) {
      std::vector<std::string> names;
      for (const Joint& j : model.upstream_joints) names.push_back(j.name);
      const std::string joints = fmt::format("{}", fmt::join(names, ", "));
      assumption =
          motion.sensor_at_rest
              ? fmt::format(
                    "assumed: the sensor frame at rest (--sensor-at-rest): the joints above "
                    "sensor link '{}' ({}) held still, only the joints below it move\n",
                    model.sensor_link(), joints)
              : fmt::format(
                    "assumed: the sensor frame moving with the joints above sensor link '{}' "
                    "({}), as identify counts a log with their columns; --sensor-at-rest for "
                    "those joints held still\n",
                    model.sensor_link(), joints);
    }
    // The root frame's gravity as the sensor frame sees it.
    if (opts.fixed_gravity)
      opts.sensor_gravity = fixed_sensor_gravity(model, motion.data().samples.root_gravity);
  }
  opts.offset = offset;
  const BaseParameters base = find_base_parameters(model, opts);
  if (!(model.nominal_total_mass() > 0))
    std::cerr << fmt::format(
        "massid: warning: {}: no measured link has a mass (no <inertial> below sensor link "
        "'{}'): the base parameters are the URDF's structure only; simulate cannot make data "
        "from it, and identify judges units by the robot's size alone\n",
        c.urdf, model.sensor_link());
  if (as_json && !assumption.empty()) std::cerr << "massid: note: " << assumption;
  std::cout << (as_json ? params_json(model, base, nullptr)
                        : assumption + model_report(model, base));
  return 0;
}

}  // namespace

void add_model_command(CLI::App& app, ModelCommand& c) {
  c.app = app.add_subcommand("model", "Measured bodies, joints and base parameters");
  CLI::App* model = c.app;
  model->add_option("robot", c.urdf, "Robot URDF")->required();
  model->add_option("--sensor", c.sensor, "Sensor link (default: the URDF root link)");
  model->add_flag("--offset", c.offset, "Include the six sensor offsets as unknowns");
  model->add_option("--fixed", c.fixed, "Joint held still: JOINT=VALUE (rad or m); repeatable");
  model->add_flag("--json", c.as_json, "Print JSON (the params file's base_parameters, no values)");
  add_motion_options(model, c.motion, false);
  model
      ->add_option("--gravity-model", c.motion.gravity_model,
                   "With --dynamic: 'varying' (a tilting platform; default) or 'level' (the "
                   "same gravity in every sample, along --root-gravity)")
      ->check(CLI::IsMember({"level", "varying"}));
  model
      ->add_option("--gravity", c.old_gravity_model,
                   "Deprecated spelling of --gravity-model (level|varying)")
      ->check(CLI::IsMember({"level", "varying"}));
  model->add_flag("--moving-sensor", c.motion.sensor_moving,
                  "With --dynamic: the sensor frame itself moves (platform, upstream joints; the "
                  "default for a sensor below movable joints)");
  model->add_flag("--sensor-at-rest", c.motion.sensor_at_rest,
                  "With --dynamic and a sensor below movable joints: count with those joints "
                  "held still (the sensor frame at rest)");
}

int run_model(ModelCommand c) {
  if (c.app->count("--gravity")) {
    if (c.app->count("--gravity-model"))
      throw InputError("--gravity level|varying is the old spelling of --gravity-model: give one");
    std::cerr << "massid: warning: --gravity level|varying is deprecated: use --gravity-model\n";
    c.motion.gravity_model = c.old_gravity_model;
  }
  return run_model(c, c.offset, c.as_json, c.motion);
}

}  // namespace massid::cli

#include "model_command.hpp"

#include <fmt/format.h>

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
  if (motion.dynamic) {
    opts.layout = ParameterLayout::full();
    opts.fixed_gravity = motion.gravity_model == "level";
    opts.sensor_moving = motion.sensor_moving;
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
  std::cout << (as_json ? params_json(model, base, nullptr) : model_report(model, base));
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
                  "With --dynamic: the sensor frame itself moves (platform, upstream joints)");
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

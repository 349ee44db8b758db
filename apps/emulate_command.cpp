#include "emulate_command.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "hints.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"
#include "massid/emulator/emulation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"
#include "options.hpp"

namespace massid::cli {

using namespace massid::emulator;

void add_emulate_command(CLI::App& app, EmulateCommand& c) {
  c.app = app.add_subcommand(
      "emulate", "Space emulator in simulation: platform vs free-floating reference (MuJoCo)");
  CLI::App* e = c.app;
  e->add_option("robot", c.urdf, "Robot URDF")->required();
  e->add_option("params", c.params, "Params JSON from identify")->required();
  e->add_option("-o,--output", c.output, "Trace CSV to write (the identified run)")->required();
  e->add_option("--summary", c.summary, "Summary JSON to write");
  e->add_option("--platform", c.platform, "Platform geometry JSON (default: docs/emulator.md)");
  e->add_option("--spacecraft-mass", c.mass,
                "Emulated spacecraft mass, kg (default: sized to the robot, see below; 50 "
                "when only --spacecraft-inertia is given)")
      ->check(sign_check(true));
  e->add_option("--spacecraft-inertia", c.inertia,
                "Principal inertia about its centre of mass IXX,IYY,IZZ, kg m^2 (default: sized "
                "to the robot; 5,5,5 when only --spacecraft-mass is given). Neither option: 50 "
                "kg and 5,5,5 kg m^2, doubled until the free-floating reference stays within "
                "half the platform's workspace");
  e->add_option("--trajectory", c.trajectory,
                "Joint trajectory CSV: t and one column per joint (default: a smooth maneuver)");
  e->add_option("--duration", c.duration, "Seconds (default 10)")->check(sign_check(true));
  e->add_option("--rate", c.rate, "Control rate, Hz (default 1000)")->check(sign_check(true));
  e->add_option("--plant", c.plant,
                "URDF of the robot as it really is (same joints, other inertials): the simulated "
                "robot on the platform and in the reference (default: ROBOT)");
  e->add_flag("--no-tare", c.no_tare,
              "Do not tare the compensated wrench with the arm at rest before the run");
  e->add_option("--gravity", c.gravity,
                "Gravity in the sensor frame when the platform is level (default 0,0,-9.80665): "
                "sets how the sensor is mounted");
}

namespace {

// The emulator's settings as this command's options.
std::string spell_setting(massid::emulator::EmulatorSetting s) {
  using massid::emulator::EmulatorSetting;
  switch (s) {
    case EmulatorSetting::SpacecraftMass:
      return "--spacecraft-mass";
    case EmulatorSetting::SpacecraftInertia:
      return "--spacecraft-inertia";
    case EmulatorSetting::Trajectory:
      return "--trajectory";
    case EmulatorSetting::Platform:
      return "--platform";
  }
  return "";
}

// A t, joint... CSV through a clamped cubic spline (joint_trajectory.hpp).
JointTrajectory trajectory_from_csv(const Model& model, const std::string& path) {
  const CsvTable table = read_csv(path);
  const int tc = table.find("t");
  if (tc < 0) throw InputError(fmt::format("{}:{}: no column 't'", path, table.header_line));
  Eigen::VectorXd t(table.num_rows());
  for (int r = 0; r < table.num_rows(); ++r) {
    t[r] = table.number(r, tc);
    if (r > 0 && !(t[r] > t[r - 1]))
      throw InputError(fmt::format("{}:{}: times must increase", path, table.line[r]));
  }
  return spline_trajectory(t, read_joint_columns(model, table));
}

// The plant robot must move like the model the parameters belong to.
void check_same_kinematics(const Model& model, const Model& plant, const std::string& path) {
  const auto fail = [&](const std::string& what) {
    throw InputError(
        fmt::format("{}: {} differs from the robot URDF's; --plant must be the same "
                    "robot with other inertials",
                    path, what));
  };
  if (plant.num_links() != model.num_links()) fail("the number of links below the sensor");
  if (plant.num_joints() != model.num_joints()) fail("the number of joints");
  for (int i = 0; i < model.num_links(); ++i) {
    const Link& a = model.links[static_cast<std::size_t>(i)];
    const Link& b = plant.links[static_cast<std::size_t>(i)];
    if (a.name != b.name || a.parent != b.parent || a.type != b.type || a.joint != b.joint ||
        !a.origin.isApprox(b.origin, 1e-12) || !a.axis.isApprox(b.axis, 1e-12))
      fail(fmt::format("link '{}' (its joint, origin or axis)", a.name));
    // A mimic joint: the same master, multiplier and offset.
    if (a.joint_index != b.joint_index || a.joint_scale != b.joint_scale ||
        a.joint_offset != b.joint_offset)
      fail(fmt::format("link '{}' (how its joint follows '{}')", a.name,
                       a.joint_index >= 0 ? model.joints[a.joint_index].name : a.joint));
  }
}

std::vector<std::string> pose_cells(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d rpy = rpy_from_rotation(pose.linear());
  std::vector<std::string> c;
  for (int k = 0; k < 3; ++k) c.push_back(format_number(pose.translation()[k]));
  for (int k = 0; k < 3; ++k) c.push_back(format_number(rpy[k]));
  return c;
}

}  // namespace

int run_emulate(const EmulateCommand& c) {
  // The identified model, static or dynamic (a dynamic fit compensates with
  // its mass part: the motion predictor at rest gives exactly the weight).
  const ParamsFile params = read_params(c.params);
  const IdentifiedModel identified = IdentifiedModel::load(c.urdf, params);
  const Model& model = identified.model();
  const Model plant =
      c.plant.empty() ? model : hold_joints(load_urdf(c.plant, params.sensor_link), params.held);
  check_same_kinematics(model, plant, c.plant);
  // The URDF's own inertials, as static base parameters of the same model.
  BaseParameters static_base = find_base_parameters(model);
  Eigen::VectorXd nominal_values = static_base.K * nominal_standard_parameters(model);
  const IdentifiedModel nominal = IdentifiedModel::from_values(
      model, std::move(static_base), std::move(nominal_values), {}, {}, c.urdf);

  EmulationOptions o;
  o.duration = c.duration;
  o.rate = c.rate;
  o.spacecraft.mass = c.mass;
  o.spacecraft.inertia =
      parse_numbers<3>(c.inertia, "--spacecraft-inertia", "IXX,IYY,IZZ").asDiagonal();
  validate(o.spacecraft);
  if (!c.platform.empty()) o.geometry = load_geometry(c.platform);
  if (!c.gravity.empty()) {
    // Mount the sensor so that its level gravity points down the platform's -z.
    const Eigen::Vector3d g = parse_numbers<3>(c.gravity, "--gravity", "gx,gy,gz");
    o.platform_T_sensor.linear() =
        Eigen::Quaterniond::FromTwoVectors(g.normalized(), -Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
  }
  o.tare = !c.no_tare;
  if (!c.trajectory.empty()) o.trajectory = trajectory_from_csv(model, c.trajectory);
  std::string sizing;
  if (!c.app->count("--spacecraft-mass") && !c.app->count("--spacecraft-inertia")) {
    const SpacecraftSizing sized = size_spacecraft(plant, o);
    o.spacecraft = sized.spacecraft;
    sizing = fmt::format(
        "spacecraft sized to the robot: {:.4g} kg, inertia {:.4g},{:.4g},{:.4g} kg m^2 ({}x 50 kg "
        "and 5 kg m^2: the free-floating reference then moves {:.3g} m and {:.3g} deg{}); set "
        "--spacecraft-mass and --spacecraft-inertia to choose\n",
        o.spacecraft.mass, o.spacecraft.inertia(0, 0), o.spacecraft.inertia(1, 1),
        o.spacecraft.inertia(2, 2), sized.factor, sized.excursion.position_m,
        sized.excursion.angle_rad * 180 / std::numbers::pi,
        sized.factor > 1 ? ", within half the platform's workspace" : "");
  }

  std::vector<TraceRow> trace;
  const EmulationSummary runs[3] = {run_emulation(plant, identified, o, true, &trace),
                                    run_emulation(plant, nominal, o, true),
                                    run_emulation(plant, identified, o, false)};
  const char* names[3] = {"identified", "nominal", "none"};

  std::vector<std::string> header{"t"};
  for (const char* p : {"cmd", "reached", "ref"})
    for (const char* a : {"x", "y", "z", "roll", "pitch", "yaw"})
      header.push_back(fmt::format("{}_{}", p, a));
  for (int l = 1; l <= 6; ++l) header.push_back(fmt::format("leg{}", l));
  for (const char* w : {"fx", "fy", "fz", "mx", "my", "mz"}) header.push_back(w);
  for (const char* w : {"fx", "fy", "fz", "mx", "my", "mz"})
    header.push_back(std::string(w) + "_comp");
  header.push_back("supervisor");
  std::vector<std::vector<std::string>> rows;
  for (const TraceRow& r : trace) {
    std::vector<std::string> row{format_number(r.t)};
    for (const auto* pose : {&r.command, &r.reached, &r.reference})
      for (auto& cell : pose_cells(*pose)) row.push_back(cell);
    for (int l = 0; l < 6; ++l) row.push_back(format_number(r.legs[l]));
    for (int k = 0; k < 6; ++k) row.push_back(format_number(r.measured[k]));
    for (int k = 0; k < 6; ++k) row.push_back(format_number(r.compensated[k]));
    row.push_back(to_string(r.state));
    rows.push_back(std::move(row));
  }
  write_csv(c.output, header, rows);

  const double realtime = c.duration / runs[0].seconds;
  std::cout << fmt::format(
      "emulated {:.3g} s of {} on a {:.4g} kg spacecraft at {:.4g} Hz ({:.3g}x real time)\n",
      c.duration, model.name, o.spacecraft.mass, c.rate, realtime);
  std::cout << sizing;
  std::cout << fmt::format("  {:<11} {:>12} {:>12} {:>12} {:>12} {:>6}\n", "gravity", "pos max m",
                           "pos rms m", "att max deg", "att rms deg", "stops");
  nlohmann::ordered_json j;
  for (int r = 0; r < 3; ++r) {
    const EmulationSummary& s = runs[r];
    std::cout << fmt::format("  {:<11} {:>12.4g} {:>12.4g} {:>12.4g} {:>12.4g} {:>6}\n", names[r],
                             s.position_error_max_m, s.position_error_rms_m,
                             s.attitude_error_max_deg, s.attitude_error_rms_deg,
                             s.supervisor_stops);
    j[names[r]] = {{"position_error_max_m", s.position_error_max_m},
                   {"position_error_rms_m", s.position_error_rms_m},
                   {"attitude_error_max_deg", s.attitude_error_max_deg},
                   {"attitude_error_rms_deg", s.attitude_error_rms_deg},
                   {"reference_excursion_m", s.reference_excursion_m},
                   {"reference_excursion_deg", s.reference_excursion_deg},
                   {"supervisor_stops", s.supervisor_stops},
                   {"first_stop_s", s.first_stop_s >= 0 ? nlohmann::ordered_json(s.first_stop_s)
                                                        : nlohmann::ordered_json()},
                   {"stop_reason", to_string(s.stop_reason)},
                   {"stop_detail", describe_stop(s, o, spell_setting)}};
  }
  // The largest errors against the reference's excursion; in absolute terms
  // when the reference hardly moves (a light gripper on a heavy spacecraft:
  // below 1 mm or 0.05 deg a percentage of it says nothing).
  const auto relative = [&](const EmulationSummary& s) {
    const auto part = [](const char* what, double error, double excursion, double small,
                         const char* unit) {
      return excursion >= small ? fmt::format("{} {:.3g} %", what, 100 * error / excursion)
                                : fmt::format("{} {:.3g} {} (the reference: only {:.2g} {})", what,
                                              error, unit, excursion, unit);
    };
    return fmt::format(
        "{}, {}", part("position", s.position_error_max_m, s.reference_excursion_m, 1e-3, "m"),
        part("attitude", s.attitude_error_max_deg, s.reference_excursion_deg, 0.05, "deg"));
  };
  std::cout << fmt::format("reference excursion: {:.4g} m, {:.4g} deg\n",
                           runs[0].reference_excursion_m, runs[0].reference_excursion_deg);
  for (int r = 0; r < 3; ++r) {
    std::cout << fmt::format("  {:<11} largest error against the reference's excursion: {}",
                             names[r], relative(runs[r]));
    if (runs[r].supervisor_stops > 0)
      std::cout << fmt::format("; supervisor stopped at {:.3g} s ({}): {}", runs[r].first_stop_s,
                               to_string(runs[r].stop_reason),
                               describe_stop(runs[r], o, spell_setting));
    std::cout << "\n";
  }
  j["spacecraft_mass_kg"] = o.spacecraft.mass;
  j["realtime_factor"] = realtime;
  j["control_step_ns"] = runs[0].control_step_ns;
  if (!c.summary.empty()) write_file_atomically(c.summary, j.dump(2) + "\n");
  std::cout << "wrote " << c.output << (c.summary.empty() ? "" : " and " + c.summary) << "\n";
  return 0;
}

}  // namespace massid::cli

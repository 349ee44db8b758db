#include "massid/report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "massid/core/kinematics.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {
namespace {

const char* joint_type_name(JointType type, bool continuous = false) {
  if (type == JointType::Fixed) return "fixed";
  if (type == JointType::Prismatic) return "prismatic";
  return continuous ? "continuous" : "revolute";
}

}  // namespace

PredictionErrors prediction_errors(const Eigen::MatrixXd& measured,
                                   const Eigen::MatrixXd& predicted) {
  PredictionErrors e;
  const Eigen::MatrixXd d = measured - predicted;
  e.rms = (d.colwise().squaredNorm() / static_cast<double>(measured.rows())).cwiseSqrt();
  e.max = d.cwiseAbs().colwise().maxCoeff();
  e.range = measured.colwise().maxCoeff() - measured.colwise().minCoeff();
  e.percent_of_range =
      (e.range.array() > 0).select(100.0 * e.rms.array() / e.range.array(), INFINITY);
  return e;
}

std::string model_report(const Model& model, const BaseParameters& base) {
  std::string out = fmt::format("robot {} ({}), sensor link '{}'\n", model.name, model.source,
                                model.sensor_link());
  out += fmt::format("measured bodies: {} links\n", model.num_links());
  for (const Link& l : model.links) {
    out += fmt::format("  {:<20} ", l.name);
    if (l.parent < 0)
      out += "sensor link";
    else
      out += fmt::format("{} joint '{}' from '{}'", joint_type_name(l.type), l.joint,
                         model.links[l.parent].name);
    out += l.has_inertial ? fmt::format(", URDF mass {:.6g} kg\n", l.mass) : ", no <inertial>\n";
  }
  out += fmt::format("movable joints: {}\n", model.num_joints());
  for (const Joint& j : model.joints) {
    out += fmt::format("  {:<20} {:<10}", j.name, joint_type_name(j.type, j.continuous));
    if (j.limited) out += fmt::format(" [{:.6g}, {:.6g}]", j.lower, j.upper);
    if (j.limited && (j.lower != j.urdf_lower || j.upper != j.urdf_upper))
      out += fmt::format(" (URDF [{:.6g}, {:.6g}], narrowed by its mimic joints' limits)",
                         j.urdf_lower, j.urdf_upper);
    out += "\n";
  }
  if (!model.mimics.empty()) {
    out += fmt::format("mimic joints: {} (they follow their master; no column in any file)\n",
                       model.mimics.size());
    for (const MimicJoint& m : model.mimics)
      out += fmt::format("  {:<20} = {:.6g} x {}{}\n", m.name, m.multiplier, m.master,
                         m.offset == 0.0 ? "" : fmt::format(" {:+.6g}", m.offset));
  }
  for (const std::string& w : model.warnings) out += "note: " + w + "\n";
  if (base.motion())
    out += fmt::format(
        "standard parameters: {} (m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz per link; inertia "
        "about the link origin)\nmotion: gravity {}{}\n",
        base.layout.size(model), base.fixed_gravity ? "fixed (level platform)" : "varying",
        base.sensor_moving ? ", sensor frame moving" : ", sensor frame at rest");
  else
    out += fmt::format("standard parameters: {} (m, mx, my, mz per link)\n", 4 * model.num_links());
  out += fmt::format("base parameters: {}", base.num_mass());
  if (base.offset) out += fmt::format(" + 6 sensor offsets = {} unknowns", base.num_unknowns());
  out += "\n";
  for (const BaseParameter& p : base.params)
    out += fmt::format("  {:<4} [{}] = {}\n", p.name, p.unit, p.expression);
  return out;
}

std::string identify_report(const Model& model, const BaseParameters& base,
                            const IdentifySummary& s, const std::string& data_source) {
  std::string out =
      fmt::format("identified from {} samples of {} (gravity from {}), sensor link '{}'\n",
                  s.samples, data_source,
                  s.gravity_from_force      ? "the measured force direction, eq. 37"
                  : s.gravity_from_upstream ? "the joints above the sensor link"
                                            : "gx,gy,gz",
                  model.sensor_link());
  if (s.delay.applied)
    out +=
        fmt::format("wrench delay behind the joints: {:.4g} ms {}, applied\n", 1e3 * s.delay.value,
                    s.delay.estimated ? fmt::format("+- {:.2g} ms (estimated: the fit's chi^2 "
                                                    "over {} delays)",
                                                    1e3 * s.delay.std, s.delay.scan.size())
                                      : "(given)");
  if (s.rest.continuous)
    out += fmt::format(
        "rest windows of a continuous log: {} windows, {} of {} rows used ({} rows found moving "
        "by the {}; the rows around each motion dropped, and {} rows where the wrench had not "
        "settled, at most {:.3g} s after a stop)\n",
        s.rest.windows.size(), s.rest.samples, s.rest.rows, s.rest.moving, s.rest.criterion,
        s.rest.trimmed, s.rest.longest_settling);
  if (s.rest.quasi_static)
    out += fmt::format(
        "a continuous log, quasi-static throughout: the joints move at most {:.3g} rad/s, and the "
        "largest inertial wrench that gives ({:.2g} N, {:.2g} N m with the URDF's inertials) is "
        "below a quarter of the wrench noise ({:.2g} N, {:.2g} N m): all {} rows used (the rest "
        "windows would keep {})\n",
        s.rest.max_speed, s.rest.inertial_force, s.rest.inertial_moment, s.rest.noise_force,
        s.rest.noise_moment, s.rest.rows, s.rest.windowed_samples);
  const int uw = base.motion() ? 6 : 5;  // "kg m^2"
  out += fmt::format("  {:<10} {:>14} {:>12} {:<{}} {}\n", "name", "value", "std", "unit", uw,
                     "expression");
  for (int i = 0; i < base.num_unknowns(); ++i) {
    const bool mass = i < base.num_mass();
    out += fmt::format("  {:<10} {:>14.6g} {:>12.2g} {:<{}} {}\n", base.unknown_name(i), s.value[i],
                       s.stddev[i],
                       mass ? base.params[i].unit : (i - base.num_mass() < 3 ? "N" : "N m"), uw,
                       mass ? base.params[i].expression : "sensor offset");
  }
  if (base.total_mass >= 0)
    out += fmt::format("total mass: {:.6g} kg +- {:.2g}\n", s.value[base.total_mass],
                       s.stddev[base.total_mass]);
  else
    out += "total mass: not identifiable (constant gravity with offsets: it joins offset fz)\n";
  out += fmt::format("condition number ({}): {:.4g}\n",
                     base.motion() ? "all rows, columns scaled" : "eq. 36, moment rows",
                     s.condition_number);
  out += "residual RMS:";
  for (int k = 0; k < 6; ++k)
    out += fmt::format("  {} {:.3g}", kWrenchColumns[k], s.residual_rms[k]);
  out += "\nnoise sigma (" + std::string(s.sigma_estimated ? "estimated from residuals" : "given") +
         "):";
  for (int k = 0; k < 6; ++k) out += fmt::format("  {} {:.3g}", kWrenchColumns[k], s.sigma[k]);
  out += fmt::format("\nchi2 per degree of freedom: {:.3g}\n", s.chi2_per_dof);
  for (Eigen::Index i = 0; i < s.drift_value.size(); ++i)
    out += fmt::format("  {:<34} {:>14.6g} +- {:.2g}\n", s.drift_names[i], s.drift_value[i],
                       s.drift_stddev[i]);
  if (s.robust)
    out += fmt::format("robust: {} of {} samples rejected (d > {:.3g})\n", s.outliers.size(),
                       s.samples, s.outlier_threshold);
  return out;
}

std::string physical_report(const BaseParameters& base, const PhysicalSummary& p,
                            HintSpeller spell) {
  std::string out = fmt::format(
      "physically consistent parameters ({}{}):\n", spell({Hint::Setting::Physical, "on"}),
      p.static_layout ? "; inertia about each centre of mass from the URDF" : "");
  out += fmt::format("  {:<20} {:>11} {:>10} {:>10} {:>10} {:>11} {:>11} {:>11}  {}\n", "link",
                     "m [kg]", "cx [m]", "cy [m]", "cz [m]", "I1 [kg m^2]", "I2", "I3",
                     "consistent (min eig J)");
  for (const PhysicalLink& l : p.links)
    out += fmt::format(
        "  {:<20} {:>11.5g} {:>10.4g} {:>10.4g} {:>10.4g} {:>11.4g} {:>11.4g} "
        "{:>11.4g}  {} ({:.2g}){}\n",
        l.name, l.mass, l.com.x(), l.com.y(), l.com.z(), l.principal_moments[0],
        l.principal_moments[1], l.principal_moments[2], l.consistent ? "yes" : "NO",
        l.min_eigenvalue,
        l.unseen
            ? "  no mass in the URDF, fixed to a neighbour: massless (its share is the neighbour's)"
        : l.prior_body ? "  no mass in the URDF: tiny prior body"
                       : "");
  if (p.worst >= 0)
    out += fmt::format(
        "worst base-parameter mismatch (K pi_phys - identified) / std: {} {:+.3g} std ({})\n",
        base.params[p.worst].name, p.worst_mismatch,
        std::abs(p.worst_mismatch) <= 1.0 ? "within std"
        : std::abs(p.worst_mismatch) <= 3.0
            ? "within 3 std: the URDF's bodies pull there"
            : "beyond 3 std: no real bodies reproduce the estimate");
  out += fmt::format("solver: {} iterations, {:.3g} ms, cost {:.4g}{}\n", p.iterations,
                     1e3 * p.solve_seconds, p.cost, p.converged ? "" : " (not converged)");
  return out;
}

std::string prediction_report(const PredictionErrors& e, int samples) {
  std::string out =
      fmt::format("prediction error over {} samples (measured - predicted):\n", samples);
  out += fmt::format("  {:<4} {:>12} {:>12} {:>12} {:>10}\n", "axis", "rms", "max", "range",
                     "rms/range");
  for (int k = 0; k < 6; ++k)
    out += fmt::format("  {:<4} {:>12.4g} {:>12.4g} {:>12.4g} {:>10}\n", kWrenchColumns[k],
                       e.rms[k], e.max[k], e.range[k],
                       std::isfinite(e.percent_of_range[k])
                           ? fmt::format("{:.3g}%", e.percent_of_range[k])
                           : "n/a");
  return out;
}

std::string design_report(const Model& model, const BaseParameters& base, const DesignSummary& s,
                          const DesignOptions& o, const std::string& evaluated, HintSpeller spell) {
  using Setting = Hint::Setting;
  const std::string no_clearance = spell({Setting::MinHeight, "none"});
  std::string out =
      evaluated.empty()
          ? fmt::format(
                "plan: {} poses for {} (sensor link '{}'), criterion {}, optimised in {:.2f} s\n",
                s.plan.size(), model.name, model.sensor_link(),
                o.criterion == Criterion::Cond ? "cond (eq. 36)" : "d-opt", s.seconds)
          : fmt::format("plan {}: {} poses for {} (sensor link '{}')\n", evaluated, s.plan.size(),
                        model.name, model.sensor_link());
  out += fmt::format("order: {} tilt changes, joint travel {:.3g} (rad or m)\n", s.tilt_changes,
                     s.joint_travel);
  if (evaluated.empty() && s.level_poses > 0)
    out += fmt::format(
        "level poses: {} of {} kept level, so that fz varies (it separates the total mass from "
        "the fz offset); {} lets the optimiser tilt every pose\n",
        s.level_poses, s.plan.size(), spell({Setting::LevelPoses, "0"}));
  const std::string meshes =
      s.links_with_meshes > 0
          ? fmt::format(
                " ({} link{} collision meshes: checked at their origin and centre of "
                "mass only)",
                s.links_with_meshes, s.links_with_meshes == 1 ? " has" : "s have")
          : "";
  // A wrist: the arm's poses are kept above the floor (design.hpp).
  const std::string plane = model.num_upstream_joints() > 0
                                ? "the floor (through the URDF root's origin, normal to the root "
                                  "gravity; the arm's links kept apart by the self-clearance)"
                                : "the platform plane (through the sensor origin, normal to level "
                                  "gravity)";
  if (s.min_height_relaxed && evaluated.empty())
    out += fmt::format(
        "clearance: not applied: no pose keeps every moving point {:.3g} m above the platform "
        "plane (through the sensor origin, normal to level gravity); {} requires a height\n",
        o.min_height.value_or(kDefaultMinHeight), spell({Setting::MinHeight, ""}));
  else if (o.min_height && evaluated.empty())
    out += fmt::format(
        "clearance: every moving link origin, centre of mass and primitive collision shape at "
        "least {:.3g} m above {}{}; lowest {:.3g} m ('{}'); {} sets it, {} turns it off\n",
        *o.min_height, plane, meshes, s.lowest_clearance, s.lowest_link,
        spell({Setting::MinHeight, ""}), no_clearance);
  else if (evaluated.empty())
    out += fmt::format(
        "clearance: not constrained ({}): poses may put links below the platform plane\n",
        no_clearance);
  else if (std::isfinite(s.lowest_clearance))
    out += fmt::format(
        "clearance: the lowest moving link origin, centre of mass or primitive collision shape "
        "is {:.3g} m {} {} ('{}'){}\n",
        std::abs(s.lowest_clearance), s.lowest_clearance < 0 ? "below" : "above", plane,
        s.lowest_link,
        o.min_height && !s.min_height_relaxed && s.lowest_clearance < *o.min_height
            ? fmt::format(", closer than {} m",
                          spell({Setting::MinHeight, fmt::format("{:.3g}", *o.min_height)}))
            : "");
  out += fmt::format("condition number (eq. 36, moment rows): {:.4g}\n", s.condition_number);
  if (!s.identifiable) return out + "the plan does not determine every base parameter\n";
  out += fmt::format(
      "predicted standard deviations at sensor noise {:.3g} N, {:.3g} N m (log det of the "
      "information matrix {:.4g}):\n",
      o.noise_force, o.noise_moment, s.log_det);
  for (int i = 0; i < base.num_unknowns(); ++i) {
    const bool mass = i < base.num_mass();
    out += fmt::format("  {:<10} {:>12.3g} {:<5} {}\n", base.unknown_name(i), s.predicted_std[i],
                       mass ? base.params[i].unit : (i - base.num_mass() < 3 ? "N" : "N m"),
                       mass ? base.params[i].expression : "sensor offset");
  }
  out +=
      "expected error of the predicted wrench (RMS over random poses within the constraints):\n ";
  for (int k = 0; k < 6; ++k)
    out += fmt::format(" {} {:.3g}", kWrenchColumns[k], s.expected_error[k]);
  return out + "\n";
}

}  // namespace massid

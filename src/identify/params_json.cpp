// Writing a params file (JSON, "massid-params-1", params_file.hpp reads it):
// an identification's base parameters with their terms, values, standard
// deviations, covariance and fit statistics, and the physical fit.
#include "massid/identify/params_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "massid/core/regressor.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {
namespace {

using json = nlohmann::ordered_json;

json terms_json(const Model& model, const std::vector<Term>& terms) {
  json out = json::array();
  for (const Term& t : terms)
    out.push_back({{"link", model.links[t.link].name},
                   {"param", standard_parameter_kind(t.param)},
                   {"coef", t.coef}});
  return out;
}

// Three entries of v from `start`: a force, a moment or a gravity vector.
json three(const Eigen::Ref<const Eigen::VectorXd>& v, int start) {
  return json::array({v[start], v[start + 1], v[start + 2]});
}

// A value per wrench axis, keyed fx .. mz.
json per_axis(const Eigen::Matrix<double, 6, 1>& v) {
  json out;
  for (int k = 0; k < 6; ++k) out[kWrenchColumns[k]] = v[k];
  return out;
}

// The "physical" section: the ten parameters of every link under "links",
// then what the fit says about them.
json physical_json(const Model& model, const BaseParameters& base, const PhysicalSummary& p) {
  json links = json::object();
  for (int l = 0; l < model.num_links(); ++l) {
    json e = json::object();
    for (int k = 0; k < 10; ++k) e[ParameterLayout::kind_name(k)] = p.standard[10 * l + k];
    links[model.links[l].name] = e;
  }
  json out;
  out["links"] = links;
  out["inertia_about"] = "link origin";
  out["inertia_from"] = p.static_layout ? "urdf (about the centre of mass)" : "data and urdf";
  out["consistent"] = p.consistent();
  json prior = json::array();
  json massless = json::array();
  for (const PhysicalLink& l : p.links) {
    if (l.prior_body) prior.push_back(l.name);
    if (l.unseen) massless.push_back(l.name);
  }
  out["massless_links"] = massless;
  out["tiny_prior_bodies"] = prior;
  json mismatch = json::object();
  for (int i = 0; i < base.num_mass(); ++i) mismatch[base.params[i].name] = p.mismatch[i];
  out["mismatch_std"] = mismatch;
  if (p.worst >= 0)
    out["worst_mismatch"] = {{"name", base.params[p.worst].name}, {"std", p.worst_mismatch}};
  // No solve time: the file is the same for the same data (CLI and Python alike).
  out["solver"] = {{"cost", p.cost}, {"iterations", p.iterations}, {"converged", p.converged}};
  return out;
}

}  // namespace

std::string params_json(const Model& model, const BaseParameters& base, const IdentifySummary* s,
                        const PhysicalSummary* physical) {
  json j;
  j["format"] = kParamsFormat;
  j["sensor_link"] = model.sensor_link();
  // The joints whose columns the fit used: below the sensor link, then the
  // ones above it when they gave gravity or the sensor frame's motion (a
  // wrist sensor), also listed under "upstream_joints".
  json joints = json::array(), upstream = json::array();
  for (const Joint& jt : model.joints) joints.push_back(jt.name);
  // (A log's pose columns, Model::pose, are no joints: "gravity_from" names them.)
  if (s && model.num_upstream_joints() > 0 && model.pose == SensorPoseColumns::None &&
      (s->gravity_from_upstream || base.sensor_moving))
    for (const Joint& jt : model.upstream_joints) {
      joints.push_back(jt.name);
      upstream.push_back(jt.name);
    }
  j["joints"] = joints;
  if (!upstream.empty()) j["upstream_joints"] = upstream;
  if (!model.held.empty()) {
    json held = json::object();
    for (const auto& [name, value] : model.held) held[name] = value;
    j["held_joints"] = held;
  }
  if (s) {
    j["gravity_from"] =
        s->gravity_from_force ? "force"
        : s->gravity_from_upstream
            ? (model.pose == SensorPoseColumns::None ? "upstream joints" : "sensor pose")
            : "columns";
    j["samples"] = s->samples;
    if (s->delay.applied) j["delay"] = {{"value", s->delay.value}, {"std", s->delay.std}};
    if (s->rest.continuous)
      j["rest_windows"] = {{"windows", s->rest.windows.size()},
                           {"samples", s->rest.samples},
                           {"rows", s->rest.rows},
                           {"moving", s->rest.moving},
                           {"criterion", s->rest.criterion},
                           {"trimmed", s->rest.trimmed},
                           {"longest_settling", s->rest.longest_settling}};
    if (s->rest.quasi_static)
      j["quasi_static"] = {{"rows", s->rest.rows},
                           {"windowed_samples", s->rest.windowed_samples},
                           {"max_speed", s->rest.max_speed},
                           {"inertial_force", s->rest.inertial_force},
                           {"inertial_moment", s->rest.inertial_moment},
                           {"noise_force", s->rest.noise_force},
                           {"noise_moment", s->rest.noise_moment}};
    if (base.total_mass >= 0) j["total_mass"] = s->value[base.total_mass];
  }
  if (base.motion()) {
    j["model"] = "dynamic";
    json motion;
    motion["gravity"] = base.fixed_gravity ? "fixed" : "varying";
    if (base.fixed_gravity) motion["gravity_vector"] = three(base.sensor_gravity, 0);
    motion["sensor_moving"] = base.sensor_moving;
    j["motion"] = motion;
  }
  json list = json::array();
  const Eigen::VectorXd scale = parameter_scales(model, base, s);
  for (int i = 0; i < base.num_mass(); ++i) {
    const BaseParameter& p = base.params[i];
    json e;
    e["name"] = p.name;
    if (s) {
      e["value"] = s->value[i];
      e["std"] = s->stddev[i];
    }
    if (std::isfinite(scale[i])) e["scale"] = scale[i];  // report.hpp: what the std is judged by
    e["unit"] = p.unit;
    e["expression"] = p.expression;
    e["terms"] = terms_json(model, p.terms);
    list.push_back(e);
  }
  j["base_parameters"] = list;
  if (base.offset) {
    if (s) {
      const Eigen::VectorXd v = s->value.tail(6), d = s->stddev.tail(6);
      j["sensor_offset"] = {{"force", three(v, 0)},
                            {"moment", three(v, 3)},
                            {"force_std", three(d, 0)},
                            {"moment_std", three(d, 3)}};
    } else {
      j["sensor_offset"] = {{"force", "estimated"}, {"moment", "estimated"}};
    }
  }
  if (s) {
    j["condition_number"] = s->condition_number;
    j["residual_rms"] = per_axis(s->residual_rms);
    j["residual_max"] = per_axis(s->residual_max);
    j["noise_sigma"] = per_axis(s->sigma);
    j["noise_sigma_from"] = s->sigma_estimated ? "residuals" : "user";
    j["chi2_per_dof"] = s->chi2_per_dof;
    // Outlier test: rejected samples (robust) or suspect ones, by file line.
    json lines = json::array();
    for (const Outlier& o : s->outliers) lines.push_back(o.line);
    // A streamed fit tested the largest residual of each axis (threshold in
    // sigmas of that axis) instead of each sample's d.
    j["outliers"] = {{"method", s->robust            ? "rejected"
                                : s->per_sample_test ? "reported"
                                                     : "largest residual"},
                     {"threshold", s->per_sample_test ? s->outlier_threshold
                                                      : largest_residual_bound(s->samples)},
                     {"count", s->outliers.size()},
                     {"fraction", s->samples ? double(s->outliers.size()) / s->samples : 0.0},
                     {"lines", lines}};
    if (s->drift != Drift::None) {
      json terms = json::array();
      for (Eigen::Index i = 0; i < s->drift_value.size(); ++i)
        terms.push_back({{"name", s->drift_names[i]},
                         {"value", s->drift_value[i]},
                         {"std", s->drift_stddev[i]}});
      j["drift"] = {{"model", s->drift == Drift::Linear ? "linear" : "per-block"},
                    {"offsets_at", s->drift == Drift::Linear ? "end of the log" : "last block"},
                    {"terms", terms}};
    }
    json names = json::array();
    for (int i = 0; i < base.num_unknowns(); ++i) names.push_back(base.unknown_name(i));
    json cov = json::array();
    for (const auto& row : s->covariance.rowwise())
      cov.push_back(std::vector<double>(row.begin(), row.end()));
    j["covariance"] = {{"unknowns", names}, {"matrix", cov}};
  }
  if (physical) j["physical"] = physical_json(model, base, *physical);
  return j.dump(2) + "\n";
}

}  // namespace massid

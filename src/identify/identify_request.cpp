#include "massid/identify/identify_request.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "identify/identify_file.hpp"
#include "massid/identify/delay.hpp"
#include "massid/identify/physical.hpp"
#include "massid/identify/rest_windows.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"

namespace massid {

namespace {

// The library's own words for the settings the rules name.
std::string library_name(Hint::Setting s) {
  using S = Hint::Setting;
  static const std::map<S, std::string> names{{S::Drift, "drift"},
                                              {S::Rest, "rest"},
                                              {S::Delay, "delay"},
                                              {S::Dynamic, "dynamic"},
                                              {S::Cutoff, "cutoff"},
                                              {S::SigmaForce, "sigma_force"},
                                              {S::SigmaMoment, "sigma_moment"},
                                              {S::RootGravity, "root_gravity"},
                                              {S::LevelGravity, "level_gravity"}};
  const auto it = names.find(s);
  return it == names.end() ? "setting" : it->second;
}

std::string library_spell(const Hint& h) {
  return h.value.empty() ? library_name(h.setting) : library_name(h.setting) + "=" + h.value;
}

// A number of seconds, or nothing.
std::optional<double> seconds(const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Whether a data file has every joint's velocity column (JOINT_vel or
// JOINT_deg_vel), the sign of a log in motion; read as the fit read it.
bool has_velocity_columns(const Model& model, const std::string& path, const SampleOptions& read) {
  if (model.num_joints() == 0) return false;
  std::vector<std::string> roles;
  read_samples_head(model, path, 1, &roles, read);
  for (const Joint& j : model.joints)
    if (std::find(roles.begin(), roles.end(), j.name + "_vel") == roles.end() &&
        std::find(roles.begin(), roles.end(), j.name + "_deg_vel") == roles.end())
      return false;
  return true;
}

}  // namespace

void IdentifyRequest::validate(const SettingSpelling& spelling) const {
  const auto name = [&](Hint::Setting s) {
    return spelling.name ? spelling.name(s) : library_name(s);
  };
  const auto spell = [&](Hint::Setting s, const std::string& value) {
    const Hint h{s, value};
    return spelling.spell ? spelling.spell(h) : library_spell(h);
  };
  using S = Hint::Setting;
  // What each word may be.
  if (!drift.empty() && drift != "linear" && drift != "per-block")
    throw InputError(fmt::format("{}: '{}' is not 'linear' or 'per-block'", name(S::Drift), drift));
  if (!rest.empty() && rest != "auto" && rest != "off")
    throw InputError(fmt::format("{}: '{}' is not 'auto' or 'off'", name(S::Rest), rest));
  if (!delay.empty() && delay != "auto" && !seconds(delay))
    throw InputError(
        fmt::format("{}: '{}' is not 'auto' or a number of seconds", name(S::Delay), delay));
  if (cutoff && !(*cutoff > 0 && std::isfinite(*cutoff)))
    throw InputError(fmt::format("{}: {} is not a positive number (Hz)", name(S::Cutoff), *cutoff));
  for (const auto& [value, setting] :
       {std::pair{sigma_force, S::SigmaForce}, std::pair{sigma_moment, S::SigmaMoment}})
    if (value && !(*value > 0 && std::isfinite(*value)))
      throw InputError(fmt::format("{}: {} is not a positive number", name(setting), *value));
  for (const auto& [value, setting] :
       {std::pair{root_gravity, S::RootGravity}, std::pair{level_gravity, S::LevelGravity}})
    if (value && !(value->allFinite() && value->norm() > 0))
      throw InputError(fmt::format("{}: {},{},{} is not a finite, non-zero gravity vector",
                                   name(setting), (*value)[0], (*value)[1], (*value)[2]));
  // The combinations.
  if (dynamic && !rest.empty())
    throw InputError(fmt::format("{} goes with static identification ({} uses every row)",
                                 name(S::Rest), spell(S::Dynamic, "on")));
  if (!dynamic && !delay.empty())
    throw InputError(fmt::format("{} goes with {} (a motion log): at rest a lag does not matter",
                                 name(S::Delay), spell(S::Dynamic, "on")));
  if (!dynamic && cutoff)
    throw InputError(fmt::format("{} goes with {} (identification in motion)", name(S::Cutoff),
                                 spell(S::Dynamic, "on")));
}

IdentifyOptions IdentifyRequest::options() const {
  IdentifyOptions o;
  o.robust = robust;
  o.sigma_force = sigma_force;
  o.sigma_moment = sigma_moment;
  if (drift == "linear") o.drift = Drift::Linear;
  if (drift == "per-block") o.drift = Drift::PerBlock;
  if (rest == "off") o.rest.detection = RestDetection::Off;
  if (delay == "auto")
    o.delay_auto = true;
  else if (!delay.empty())
    o.delay = seconds(delay);
  if (physical) {
    o.physical = PhysicalOptions{};
    if (physical_iterations > 0) o.physical->max_iterations = physical_iterations;
  }
  return o;
}

MotionDataOptions IdentifyRequest::motion_options() const {
  MotionDataOptions o;
  if (cutoff) o.filter.cutoff = *cutoff;
  if (root_gravity) o.samples.root_gravity = *root_gravity;
  o.samples.level_gravity = level_gravity;
  o.samples.columns = columns;
  o.samples.sensor_motion = dynamic;
  return o;
}

Model IdentifyRequest::load_model(const std::string& urdf) const {
  return hold_joints(load_urdf(urdf, sensor_link), held);
}

Identification identify(Model model, const IdentifyRequest& request, IdentifySource source) {
  request.validate();
  const IdentifyOptions options = request.options();
  const MotionDataOptions motion = request.motion_options();
  const bool with_offset = request.with_offset();
  const bool in_memory = source.samples.has_value();
  const bool velocity_in_memory = in_memory && source.samples->qd.cols() > 0;
  const std::string name = in_memory ? source.samples->source : source.path;
  Identification out;
  out.model = std::move(model);
  Samples* kept = request.keep_samples ? &out.samples : nullptr;
  if (request.dynamic && (in_memory || options.delay || options.delay_auto)) {
    // In memory: the wrench moved by the delay (estimated by a scan of fits), then the fit.
    out.motion_options = motion;
    Samples raw = in_memory ? std::move(*source.samples)
                            : read_samples(out.model, read_csv(source.path),
                                           WrenchColumns::Required, motion.samples);
    DelayEstimate delay;
    out.samples = aligned_motion_samples(out.model, std::move(raw), with_offset, options, motion,
                                         &delay, &out.motion);
    out.base = find_base_parameters(out.model, motion_base_options(out.samples, with_offset));
    out.summary = identify(out.model, out.base, out.samples, options);
    out.summary.delay = std::move(delay);
  } else if (request.dynamic) {
    out.motion_options = motion;
    out.summary = identify_motion_file(out.model, source.path, with_offset, options, motion,
                                       &out.base, &out.motion, kept);
    if (kept && out.samples.size() < out.summary.samples)  // streamed: only the head came back
      out.samples = read_motion_samples(out.model, source.path, WrenchColumns::Required, motion);
  } else {
    try {
      BaseParameterOptions bo;
      bo.offset = with_offset;
      out.base = find_base_parameters(out.model, bo);
      if (in_memory) {  // as identify_file: only the rest windows of a continuous log
        out.summary = identify_at_rest(out.model, out.base, std::move(*source.samples), options,
                                       &out.samples);
      } else {
        out.summary =
            identify_file(out.model, out.base, source.path, options, kept, motion.samples);
      }
    } catch (const IdentifiabilityError& e) {
      // A motion log identified at rest: its weight alone cannot determine what
      // the motion moves; the fix is --dynamic, not more poses.
      if (!(in_memory ? velocity_in_memory
                      : has_velocity_columns(out.model, source.path, motion.samples)))
        throw;
      throw IdentifiabilityError(
          fmt::format("{}: this file has velocity columns: a log in motion, which the weight alone "
                      "does not explain (identified at rest, {}); identify it in motion",
                      name,
                      std::string(e.what())
                          .substr(0, std::string(e.what()).find(". To fix"))
                          .substr(std::string(e.what()).find(": ") + 2)),
          {{Hint::Setting::Dynamic, "on"}});
    }
  }
  if (request.checks)
    if (std::optional<SetupFinding> wrong =
            check_fitted_weight(out.model, out.base, out.summary, name))
      throw SetupRefused({std::move(*wrong)});
  if (request.keep_samples)
    out.fitted = fitted_wrenches(out.model, out.base, out.samples, out.summary);
  else
    out.samples = Samples{};
  if (options.physical)
    out.physical = fit_physical(out.model, out.base, out.summary, *options.physical);
  out.warnings = identification_notes(out.summary, name);
  return out;
}

}  // namespace massid

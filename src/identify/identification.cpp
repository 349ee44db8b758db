#include "massid/identify/identification.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>
#include <utility>

#include "identify/identify_file.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/delay.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"

namespace massid {

std::vector<Warning> identification_notes(const IdentifySummary& summary,
                                          const std::string& source) {
  std::vector<Warning> out;
  if (summary.gravity_from_force)
    out.push_back({fmt::format("{} has no gx,gy,gz columns: gravity is taken along the measured "
                               "force (paper eq. 37), |g| = {} m/s^2",
                               source, kStandardGravity),
                   {}});
  for (Warning& w : identify_warnings(summary, source)) out.push_back(std::move(w));
  return out;
}

}  // namespace massid

// ---------------------------------------------------------------------------
// The record file

// A matrix as {rows, cols, data: the column-major doubles' bytes}; a
// fixed-size one (a 6- or 3-vector) must come back with its size.
template <int R, int C, int Options, int MaxR, int MaxC>
struct nlohmann::adl_serializer<Eigen::Matrix<double, R, C, Options, MaxR, MaxC>> {
  using Matrix = Eigen::Matrix<double, R, C, Options, MaxR, MaxC>;
  static_assert(!(Options & Eigen::RowMajor), "column-major data");
  static void to_json(json& j, const Matrix& m) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.size()) * sizeof(double));
    if (!bytes.empty()) std::memcpy(bytes.data(), m.data(), bytes.size());
    j = {{"rows", m.rows()}, {"cols", m.cols()}, {"data", json::binary(std::move(bytes))}};
  }
  static void from_json(const json& j, Matrix& m) {
    const Eigen::Index rows = j.at("rows").get<Eigen::Index>(),
                       cols = j.at("cols").get<Eigen::Index>();
    const auto& bytes = j.at("data").get_binary();
    if (rows < 0 || cols < 0 ||
        bytes.size() != static_cast<std::size_t>(rows * cols) * sizeof(double))
      throw std::runtime_error("a matrix's size does not match its data");
    if ((R != Eigen::Dynamic && rows != R) || (C != Eigen::Dynamic && cols != C))
      throw std::runtime_error("a vector has the wrong size");
    m.resize(rows, cols);
    if (!bytes.empty()) std::memcpy(m.data(), bytes.data(), bytes.size());
  }
};

namespace massid {

// The record's parts, each member under its own name (the physical fit's
// per-link summaries and IdentifySummary::beyond_noise are not recorded).
// An outlier as [sample, line, score], a rest window as [first, last].
void to_json(nlohmann::json& j, const Outlier& o) { j = {o.sample, o.line, o.score}; }
void from_json(const nlohmann::json& j, Outlier& o) { o = {j.at(0), j.at(1), j.at(2)}; }
void to_json(nlohmann::json& j, const RestWindow& w) { j = {w.first, w.last}; }
void from_json(const nlohmann::json& j, RestWindow& w) { w = {j.at(0), j.at(1)}; }
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RestWindows, continuous, windows, rows, samples, moving,
                                   criterion, trimmed, longest_settling, quasi_static,
                                   inertia_checked, max_speed, inertial_force, inertial_moment,
                                   noise_force, noise_moment, windowed_samples)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DelayEstimate, applied, estimated, value, std, scan)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(IdentifySummary, value, stddev, covariance, condition_number,
                                   residual_rms, residual_max, sigma, residual_dof, sigma_estimated,
                                   sigma_force_given, sigma_moment_given, chi2_per_dof, samples,
                                   gravity_from_force, gravity_from_upstream, outliers,
                                   outlier_threshold, per_sample_test, robust, drift, drift_names,
                                   drift_value, drift_stddev, rest, delay)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PhysicalSummary, standard, mismatch, worst, worst_mismatch,
                                   static_layout, initial_cost, cost, iterations, solve_seconds,
                                   converged, message)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Samples, source, q, qd, qdd, q_upstream, qd_upstream,
                                   qdd_upstream, gravity, sensor_motion, wrench, line, time, block,
                                   gravity_from_force, gravity_from_upstream, derivatives_filtered,
                                   noise_lags, root_gravity)

namespace {

using record_json = nlohmann::json;
constexpr const char* kRecordFormat = "massid-identification-1";
static_assert(std::endian::native == std::endian::little, "records store little-endian doubles");

// The settings by name, in the order of Hint::Setting (a record names them:
// the enumeration may grow).
constexpr const char* kSettingNames[] = {
    "hold_joints", "offset",       "checks",     "robust",      "drift",         "dynamic",
    "cutoff",      "delay",        "min_height", "limits",      "level_gravity", "tilt_max",
    "physical",    "sensor_link",  "poses",      "sigma_force", "sigma_moment",  "level_poses",
    "rest",        "root_gravity", "columns"};
static_assert(std::size(kSettingNames) == static_cast<std::size_t>(Hint::Setting::Columns) + 1,
              "a name for every setting");

record_json warnings_json(const std::vector<Warning>& warnings, HintSpeller spell) {
  record_json out = record_json::array();
  for (const Warning& w : warnings) {
    record_json hints = record_json::array();
    std::string message = w.message;
    if (spell && !w.hints.empty()) {  // as the caller prints it: cli::with_hints
      message += " (";
      for (std::size_t i = 0; i < w.hints.size(); ++i)
        message += (i ? "; " : "") + spell(w.hints[i]);
      message += ")";
    } else {
      for (const Hint& h : w.hints)
        hints.push_back(
            {{"setting", kSettingNames[static_cast<std::size_t>(h.setting)]}, {"value", h.value}});
    }
    out.push_back({{"message", message}, {"hints", hints}});
  }
  return out;
}

// Either form: {message, hints} or, in older records, the message alone.
std::vector<Warning> warnings_of(const record_json& j) {
  std::vector<Warning> out;
  for (const record_json& w : j) {
    if (w.is_string()) {
      out.push_back({w.get<std::string>(), {}});
      continue;
    }
    Warning warning{w.at("message").get<std::string>(), {}};
    for (const record_json& h : w.at("hints")) {
      const std::string name = h.at("setting").get<std::string>();
      const auto* at = std::find(std::begin(kSettingNames), std::end(kSettingNames), name);
      if (at == std::end(kSettingNames))
        throw std::runtime_error(fmt::format("a warning's hint names no setting ('{}')", name));
      warning.hints.push_back({static_cast<Hint::Setting>(at - std::begin(kSettingNames)),
                               h.at("value").get<std::string>()});
    }
    out.push_back(std::move(warning));
  }
  return out;
}

// Fields that older records lack (RestWindows' since the settling and the
// quasi-static checks, Samples::noise_lags: independent rows): their
// defaults.
void add_defaults(record_json& j, const record_json& defaults,
                  std::initializer_list<const char*> keys) {
  for (const char* key : keys) j.emplace(key, defaults.at(key));
}

// The base parameters' expressions: a record names them to check the URDF's.
std::vector<std::string> expressions(const BaseParameters& b) {
  std::vector<std::string> names;
  for (const BaseParameter& p : b.params) names.push_back(p.expression);
  return names;
}

// The physical fit: its ten parameters per link and figures; the per-link
// summaries are derived again on reading (physical_link).
record_json physical_json(const PhysicalSummary& p) {
  std::vector<bool> prior;
  for (const PhysicalLink& l : p.links) prior.push_back(l.prior_body);
  record_json j = p;
  j["prior_body"] = prior;
  return j;
}

PhysicalSummary physical_of(const record_json& j, const Model& model) {
  PhysicalSummary p = j;
  const std::vector<bool> prior = j.at("prior_body").get<std::vector<bool>>();
  if (p.standard.size() != 10 * model.num_links() ||
      prior.size() != static_cast<std::size_t>(model.num_links()))
    throw std::runtime_error("its physical parameters do not fit the model");
  for (int l = 0; l < model.num_links(); ++l) {
    p.links.push_back(physical_link(model.links[l].name, p.standard.segment<10>(10 * l)));
    p.links.back().prior_body = prior[l];
    p.links.back().unseen = prior[l] && p.standard.segment<10>(10 * l).isZero(0.0);
  }
  return p;
}

}  // namespace

void write_identification(const std::string& path, const Identification& ident, HintSpeller spell) {
  const BaseParameters& b = ident.base;
  const MotionDataReport& m = ident.motion;
  const MotionDataOptions& mo = ident.motion_options;
  record_json j = {{"format", kRecordFormat},
                   {"urdf", std::filesystem::absolute(ident.model.source).string()},
                   {"sensor_link", ident.model.sensor_link()},
                   {"held", ident.model.held},  // [name, value] pairs
                   {"base",
                    {{"per_link", b.layout.per_link()},
                     {"sensor_moving", b.sensor_moving},
                     {"fixed_gravity", b.fixed_gravity},
                     {"gravity", b.sensor_gravity},
                     {"offset", b.offset},
                     {"rank_tolerance", b.rank_tolerance},
                     {"names", expressions(b)}}},
                   {"summary", ident.summary},
                   {"samples", ident.samples},
                   {"fitted", ident.fitted},
                   {"warnings", warnings_json(ident.warnings, spell)},
                   {"motion",
                    {{"rows", m.rows},
                     {"derived", m.derived},
                     {"dt", m.kernels.dt},
                     {"cutoff", m.kernels.cutoff},
                     {"decimation", m.decimation},
                     {"option_cutoff", mo.filter.cutoff},
                     {"option_decimation", mo.filter.decimation},
                     {"g0", mo.samples.g0},
                     {"root_gravity", mo.samples.root_gravity}}}};
  if (ident.physical) j["physical"] = physical_json(*ident.physical);
  const std::vector<std::uint8_t> bytes = record_json::to_cbor(j);
  write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

Identification read_identification(const std::string& path) {
  const std::string bytes = read_file(path);
  Identification out;
  try {
    record_json j = record_json::from_cbor(bytes);
    if (j.at("format") != kRecordFormat)
      throw std::runtime_error(fmt::format("format is not {}", kRecordFormat));
    out.model = hold_joints(load_urdf(j.at("urdf"), j.at("sensor_link")),
                            j.at("held").get<std::vector<std::pair<std::string, double>>>());
    const record_json& b = j.at("base");
    BaseParameterOptions bo;
    bo.layout = ParameterLayout::of_size(b.at("per_link"));
    bo.sensor_moving = b.at("sensor_moving");
    bo.fixed_gravity = b.at("fixed_gravity");
    b.at("gravity").get_to(bo.sensor_gravity);
    bo.offset = b.at("offset");
    bo.rank_tolerance = b.at("rank_tolerance");
    out.base = find_base_parameters(out.model, bo);
    if (expressions(out.base) != b.at("names").get<std::vector<std::string>>())
      throw std::runtime_error(
          "the URDF's base parameters are no longer those of the fit (was the URDF changed?)");
    add_defaults(
        j.at("summary").at("rest"), RestWindows{},
        {"trimmed", "longest_settling", "quasi_static", "inertia_checked", "max_speed",
         "inertial_force", "inertial_moment", "noise_force", "noise_moment", "windowed_samples"});
    add_defaults(j.at("samples"), Samples{}, {"noise_lags"});
    j.at("summary").get_to(out.summary);
    j.at("samples").get_to(out.samples);
    j.at("fitted").get_to(out.fitted);
    out.warnings = warnings_of(j.at("warnings"));
    const record_json& m = j.at("motion");
    out.motion.rows = m.at("rows");
    out.motion.derived = m.at("derived");
    out.motion.decimation = m.at("decimation");
    out.motion_options.filter.cutoff = m.at("option_cutoff");
    out.motion_options.filter.decimation = m.at("option_decimation");
    out.motion_options.samples.g0 = m.at("g0");
    m.at("root_gravity").get_to(out.motion_options.samples.root_gravity);
    if (out.motion.derived)
      out.motion.kernels = make_kernels(m.at("dt").get<double>(), m.at("cutoff").get<double>());
    if (j.contains("physical")) out.physical = physical_of(j.at("physical"), out.model);
    if (out.summary.value.size() != out.base.num_unknowns() ||
        out.fitted.rows() != out.samples.size())
      throw std::runtime_error("its parts do not fit together");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: not a massid identification record: {}", path, e.what()));
  }
  return out;
}

// Declared in identified_model.hpp (live), defined here with the
// identification it reads, so that the live part needs nothing of identify.
IdentifiedModel IdentifiedModel::from_identification(const Identification& ident,
                                                     const IdentifiedModelOptions& options) {
  Eigen::VectorXd values = ident.summary.value;
  if (options.physical) {
    if (!ident.physical)
      throw InputError("predicting from physical parameters needs an identification with them");
    values.head(ident.base.num_mass()) =
        base_values_of_standard(ident.model, ident.base, ident.physical->standard);
  }
  return from_values(ident.model, ident.base, std::move(values),
                     options.physical ? Eigen::VectorXd() : ident.summary.stddev,
                     options.physical ? Eigen::MatrixXd() : ident.summary.covariance,
                     "the identification")
      .with_delay(ident.summary.delay.applied ? ident.summary.delay.value : 0.0)
      .with_residual_rms(ident.summary.residual_rms);
}

}  // namespace massid

// One identification request: every choice `massid identify` and Python's
// massid.identify offer, in one object, checked in one place (validate(), in
// the style of Ceres' Solver::Options::IsValid), and identify(model, request,
// source) that runs it on a file or on samples in memory. The front ends only
// translate their own spellings (options, keywords) into a request and print
// or return the result.
//
//   IdentifyRequest r;
//   r.dynamic = true;
//   r.delay = "auto";
//   r.validate(spelling);  // InputError naming the setting as the caller spells it
//   Identification ident = identify(r.load_model(urdf), r, IdentifySource::file(path));
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

// How a front end names its settings in the messages of validate(): the
// setting alone (the CLI's "--delay", Python's "delay") and a setting with a
// value (a HintSpeller: "--dynamic", "dynamic=True"). Unset members: the
// library's own words ("delay", "dynamic=on").
struct SettingSpelling {
  std::string (*name)(Hint::Setting) = nullptr;
  HintSpeller spell = nullptr;
};

struct IdentifyRequest {
  // The model: the sensor link (empty: the URDF root link) and the joints held
  // still in the experiment (hold_joints). load_model applies them.
  std::string sensor_link;
  std::vector<std::pair<std::string, double>> held;

  bool offset = false;   // estimate the six sensor offsets
  bool dynamic = false;  // a motion log: ten parameters per link
  // A drifting offset (implies offset): "" (none), "linear" (column t) or
  // "per-block" (column block).
  std::string drift;
  // Static logs with t: "" or "auto" (only the rest windows are samples) or
  // "off" (every row). Not with dynamic.
  std::string rest;
  // Motion logs: the wrench's lag behind the joints: "" (none), "auto"
  // (estimated within +-20 ms) or seconds as a number ("0.002").
  std::string delay;
  // Motion logs without JOINT_vel/_acc: the zero-phase low-pass cut-off, Hz
  // (unset: min(10, rate/20)).
  std::optional<double> cutoff;
  // The set-up checks that need the fit (check_fitted_weight: a negative total
  // mass, i.e. a negated wrench in motion); the doors' checks of the file
  // before the fit go with the same switch.
  bool checks = true;
  bool robust = false;    // reject samples with implausible residuals
  bool physical = false;  // also fit physically consistent standard parameters
  // The physical fit's solver limit (PhysicalOptions::max_iterations); 0: its default.
  int physical_iterations = 0;
  // The noise per axis (unset: estimated from the residuals), N and N m.
  std::optional<double> sigma_force, sigma_moment;
  // Gravity in the URDF root frame, for a sensor below movable joints whose
  // columns the data have and no gx,gy,gz (unset: 0,0,-9.80665).
  std::optional<Eigen::Vector3d> root_gravity;
  // Gravity in the sensor frame with the platform level, for a log whose
  // gravity comes from tilt_x_deg,tilt_y_deg (SampleOptions::level_gravity;
  // unset: root_gravity through the fixed joints above the sensor link).
  std::optional<Eigen::Vector3d> level_gravity;
  // Columns of the log read as roles under other names (read_samples.hpp).
  ColumnNames columns;
  // Keep every sample and the fitted wrenches in the result (Python, the
  // report); without, a file is identified in constant memory.
  bool keep_samples = true;

  // Every rule, each with its one message: InputError naming the setting as
  // `spelling` spells it. The rules:
  //   drift is "", "linear" or "per-block"; rest is "", "auto" or "off";
  //   delay is "", "auto" or a finite number; cutoff, sigma_force and
  //   sigma_moment are positive and finite; root_gravity and level_gravity
  //   are finite and not zero; rest goes with static identification; delay and cutoff go with
  //   dynamic.
  void validate(const SettingSpelling& spelling = {}) const;

  // The offsets are unknowns (offset, or a drift).
  bool with_offset() const { return offset || !drift.empty(); }
  // The estimator's options (validate() first: they assume a valid request).
  IdentifyOptions options() const;
  // How a log is read (root and level gravity, column names; the sensor motion needed
  // only when dynamic) and, in motion, filtered (cutoff).
  MotionDataOptions motion_options() const;
  SampleOptions sample_options() const { return motion_options().samples; }
  // load_urdf(urdf, sensor_link) with the held joints held.
  Model load_model(const std::string& urdf) const;
};

// What to identify from: a data file (streamed where it can be, as `massid
// identify`), or samples in memory as read (read_samples or
// samples_from_columns with request.sample_options(); before rest windows
// and, in motion, before filtering).
struct IdentifySource {
  std::string path;
  std::optional<Samples> samples;

  static IdentifySource file(std::string path) { return {std::move(path), std::nullopt}; }
  static IdentifySource data(Samples samples) { return {{}, std::move(samples)}; }
};

// The request run on the source: validate(), then the reduction, the fit
// (identify() of estimation.hpp, or identify_file / identify_motion_file on a
// file), the delay, the rest windows, the physical fit and the notes
// (identification_notes), as `massid identify` prints them. The set-up checks
// (setup_checks.hpp) are the caller's, before this. A file and the same
// samples in memory give the same numbers. `model` is moved into the result.
Identification identify(Model model, const IdentifyRequest& request, IdentifySource source);

}  // namespace massid

// Live gravity compensation, one CSV line at a time (`massid compensate`):
// a stream's header is bound to the model once, then every sample line is
// parsed, predicted and written out as the input text plus
//
//   fx_comp .. mz_comp = measured - predicted - offset
//
// (the same figures as `massid predict`'s _comp columns) without allocating.
//
// Columns as in a data file (samples.hpp): the joints (JOINT or JOINT_deg),
// fx..mz, and the gravity in the sensor frame from gx,gy,gz, else from the
// joints above the sensor link and the root gravity, else from
// tilt_x_deg,tilt_y_deg (the platform's tilt as design's plans write it,
// applied to the level gravity: tilted_gravity, design.hpp;
// tilt_level_gravity, read_samples.hpp). A dynamic params
// file (identified in motion) predicts the full wrench from JOINT_vel and
// JOINT_acc, and the sensor frame's motion from wx..az or the upstream joints'
// _vel/_acc. Other columns are carried through untouched.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/live/identified_model.hpp"
#include "massid/live/tracker.hpp"

namespace massid {

struct CompensatorOptions {
  // Gravity in the URDF root frame, for a sensor below movable joints whose
  // columns the stream has (and no gx,gy,gz).
  Eigen::Vector3d root_gravity{0.0, 0.0, -kStandardGravity};
  // Gravity in the sensor frame with the platform level: tilt_x_deg,tilt_y_deg
  // turn it (when the stream has no gx,gy,gz and no upstream joints). Unset:
  // root_gravity through the fixed joints above the sensor link, as every
  // reader (SampleOptions::level_gravity, tilt_level_gravity); given for a
  // stream without tilt columns: InputError.
  std::optional<Eigen::Vector3d> level_gravity;
  // Columns of the stream read as roles under other names (read_samples.hpp).
  ColumnNames columns;
  // Track a payload and the drifting offsets (tracker.hpp; `compensate
  // --track`): the stream needs t; the tracking columns follow fx_comp..mz_comp
  // (payload_m ... event, interface.md "Tracking") and *_comp becomes
  // measured - predicted(mechanism and payload) - offset.
  bool track = false;
  TrackerOptions tracker;
  // With track: time each tracker update (tracker_update_ns(); `--stats`).
  // Off, no line reads the clock.
  bool time_tracker = false;
};

class Compensator {
 public:
  // Binds the stream's header to an identified model (identified_model.hpp:
  // static or dynamic; its compensate() gives fx_comp..mz_comp). `text` ends
  // with the header line, the lines before it blank or comments (they count
  // for line numbers); `source` names the stream in messages ("stdin").
  // InputError naming the column: a joint or wrench column missing, part of
  // a group, no gravity, a fx_comp..mz_comp column already there, or a
  // dynamic model without JOINT_vel and JOINT_acc. (From a params file:
  // IdentifiedModel::load or from_params; from values: from_values.)
  Compensator(const IdentifiedModel& identified, std::string_view text, const std::string& source,
              const CompensatorOptions& options = {});
  ~Compensator();
  Compensator(Compensator&&) noexcept;
  Compensator& operator=(Compensator&&) noexcept;

  // The output header: the input header's text, then ",fx_comp,...,mz_comp\n".
  const std::string& output_header() const;
  // Notes for the user on what the stream's columns give (a static params file
  // with _vel columns: the motion is not compensated), "" when none.
  const std::string& note() const;

  // One line of the stream, without its '\n' (a trailing '\r' is dropped),
  // line_no its number for messages. Returns the output line (the input text,
  // then the six compensated values as massid writes numbers, then '\n'),
  // valid until the next call; empty for a comment line. InputError
  // "SOURCE:LINE[:COLUMN]: ..." for a malformed line (wrong field count, a
  // cell that is not a finite number, a blank line). A good line does not
  // allocate (once the output buffer holds the longest line so far).
  std::string_view compensate(std::string_view line, int line_no);

  // The last good line's compensated wrench, fx..mz.
  const Wrench& compensated() const;
  // The last good line's measured wrench, fx..mz (valid until the next call).
  Eigen::Map<const Wrench> measured() const;
  // With options.track: the tracker (its estimate after the last good line)
  // and, with options.time_tracker, the time its update took on that line,
  // ns; null and 0 otherwise.
  const Tracker* tracker() const;
  long long tracker_update_ns() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace massid

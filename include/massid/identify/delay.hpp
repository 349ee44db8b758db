// Clock alignment of a motion log: the lag of the wrench stream behind the
// joint stream, in seconds, positive when the wrench arrives late (the wrench
// logged in row i was measured at t_i - delay). At 5 Hz a lag of 1 ms turns
// the inertial wrench by 1.8 degrees of phase and costs about 3 % of it, so
// motion identification estimates it (identify --dynamic --delay auto) or
// applies a known one (--delay S) before the fit.
#pragma once

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/delay_estimate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"

namespace massid {

// The raw log with the streams aligned: row i keeps its wrench (and its
// noise) and takes the joint stream (positions, velocities, accelerations,
// gravity, sensor motion) at t_i - delay, interpolated linearly in t; without
// its first and last `margin` rows (margin >= |delay|/dt + 1 keeps every
// instant inside the log; the same margin for every delay keeps the rows the
// same). InputError without a t column.
Samples delay_wrench(const Samples& raw, double delay, int margin);

// A log to predict with a model's clock delay (IdentifiedModel::delay): every
// row takes the joint stream at t_i - delay (delay_wrench with no margin;
// instants before the log's start or after its end take its first or last
// row's), so that the prediction at row i is the wrench the sensor logs there.
// Unchanged when delay is 0. InputError without t (`model_source` names where
// the delay comes from). *note, when not null: what was applied, for the door
// to show ("" when delay is 0).
Samples delay_joint_stream(Samples samples, double delay, const std::string& model_source,
                           std::string* note = nullptr);

// The delay in [-max_delay, max_delay] whose fit leaves the least chi^2 (the
// residuals weighted by the noise of the fit at delay 0): a coarse scan in
// max_delay/8 steps, a fine one in quarter steps around its best, and the
// parabola through the best three; std = sqrt(2 / chi^2''), the curvature of
// that parabola. InputError when the best lies at the scan's edge.
DelayEstimate estimate_delay(const Model& model, const Samples& raw, bool offset,
                             const IdentifyOptions& options, const MotionDataOptions& data,
                             double max_delay = 0.02);

// The motion samples of a raw log aligned as options.delay asks (estimated
// first when options.delay_auto), then prepared (prepare_motion_samples).
// `delay` receives what was applied.
Samples aligned_motion_samples(const Model& model, Samples raw, bool offset,
                               const IdentifyOptions& options, const MotionDataOptions& data,
                               DelayEstimate* delay, MotionDataReport* report = nullptr);

}  // namespace massid

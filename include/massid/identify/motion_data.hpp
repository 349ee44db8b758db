// Motion logs: from a CSV file to samples for the dynamic model, and the
// base-parameter reduction that such data calls for.
//
// Velocities and accelerations come from the JOINT_vel / JOINT_acc columns
// when the log has them; otherwise they are derived from t and the positions
// by the zero-phase low-pass of motion_filter.hpp, applied alike to every
// other column that enters the fit ("parallel filtering"). The joints above
// the sensor link (Model::upstream) then give gravity and the sensor's motion.
#pragma once

#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/motion_filter.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

struct MotionDataOptions {
  MotionFilterOptions filter;  // used only when derivatives are derived
  SampleOptions samples;       // root gravity (upstream joints), |g| for eq. 37
};

// What read_motion_samples did, for the summary a front end prints.
struct MotionDataReport {
  int rows = 0;           // data rows in the file
  bool derived = false;   // velocities and accelerations derived from positions
  FilterKernels kernels;  // the filter (when derived)
  int decimation = 1;     // every D-th filtered sample kept (when derived)
};

// Samples with qd and qdd (given or derived), gravity and sensor motion.
// InputError: without _vel/_acc columns and without t, or t not uniform.
Samples prepare_motion_samples(const Model& model, Samples raw, const MotionDataOptions& options,
                               MotionDataReport* report = nullptr);
Samples read_motion_samples(const Model& model, const std::string& path, WrenchColumns wrench,
                            const MotionDataOptions& options, MotionDataReport* report = nullptr);

// The reduction motion samples call for: the full layout; a fixed gravity
// when every sample has the same one (a level platform); a moving sensor
// frame when the samples' sensor motion is not zero.
BaseParameterOptions motion_base_options(const Samples& samples, bool offset);

}  // namespace massid

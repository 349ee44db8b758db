// Identification of a data file, as `massid identify` does it: streamed from
// the file in constant memory (streaming.hpp) when the fit is a plain one,
// in memory for --robust and --drift, and in memory again, to name the
// samples, when a streamed log's largest residuals are implausible (and the
// file is at most 64 MB). The set-up checks (setup_checks.hpp) are the
// caller's, before this. The same for motion logs (`massid identify
// --dynamic`): identify_motion_file.
#pragma once

#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

// identify() on the rest windows of `all` when it is a continuous log
// (find_rest_windows with the model), on every sample otherwise; the windows
// in the summary's `rest`, the samples fitted in `samples` (when given).
IdentifySummary identify_at_rest(const Model& model, const BaseParameters& base, Samples all,
                                 const IdentifyOptions& options, Samples* samples = nullptr);

// The same summary as identify(model, base, read_samples(..., read)). With
// `samples` given, the file's samples are returned there too (read in
// pieces: memory for the samples alone).
IdentifySummary identify_file(const Model& model, const BaseParameters& base,
                              const std::string& path, const IdentifyOptions& options = {},
                              Samples* samples = nullptr, const SampleOptions& read = {});

// A motion log: the summary of the in-memory path
//   samples = read_motion_samples(model, path, WrenchColumns::Required, data, report)
//   base    = find_base_parameters(model, motion_base_options(samples, offset))
//   summary = identify(model, base, samples, options)
// streamed in constant memory (identify_motion_csv), or that path itself for
// options.robust / options.drift, and to name the samples of a log of at
// most 64 MB whose largest residuals are implausible. `base` receives the
// base parameters (required), `report` what was read and filtered, `head`
// (optional) the prepared samples: all of them when the fit was in memory,
// else those of the head of the file (the first 2 MB or more, see
// streaming.hpp).
IdentifySummary identify_motion_file(const Model& model, const std::string& path, bool offset,
                                     const IdentifyOptions& options, const MotionDataOptions& data,
                                     BaseParameters* base, MotionDataReport* report = nullptr,
                                     Samples* head = nullptr);

}  // namespace massid

// Identification of a data file, as `massid identify` does it: streamed from
// the file in constant memory (streaming.hpp) when the fit is a plain one,
// in memory for --robust and --drift, and in memory again, to name the
// samples, when a streamed log's largest residuals are implausible (and the
// file is at most 64 MB). The set-up checks (setup_checks.hpp) are the
// caller's, before this.
#pragma once

#include <string>

#include "massid/base_parameters.hpp"
#include "massid/estimation.hpp"
#include "massid/model.hpp"
#include "massid/samples.hpp"

namespace massid {

// The same summary as identify(model, base, read_samples(...)). With
// `samples` given, the file's samples are returned there too (read in
// pieces: memory for the samples alone).
IdentifySummary identify_file(const Model& model, const BaseParameters& base,
                              const std::string& path, const IdentifyOptions& options = {},
                              Samples* samples = nullptr);

}  // namespace massid

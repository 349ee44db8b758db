// An identification with what it was made from: the model, its base
// parameters, the fit, the samples and the fitted wrenches. The one object
// behind Python's massid.Identification and the HTML report; the CLI's
// `identify --report` hands it to the report in a file (write_identification)
// so that the report draws the fit the command printed without fitting again.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/physical.hpp"

namespace massid {

struct Identification {
  Model model;
  BaseParameters base;
  IdentifySummary summary;
  Samples samples;                   // every sample of the fit, as prepared (motion: filtered,
                                     // decimated); the rejected ones too
  Eigen::MatrixXd fitted;            // [N x 6] fitted_wrenches(model, base, samples, summary)
  std::vector<Warning> warnings;     // identification_notes: messages and hints
  MotionDataReport motion;           // dynamic: how the log became samples
  MotionDataOptions motion_options;  // dynamic: cutoff and root gravity as given
  // Physically consistent standard parameters (IdentifyOptions::physical).
  std::optional<PhysicalSummary> physical;
};

// Warnings about an identification, each message one line starting with the
// source and without a prefix or newline (the CLI prints "massid: warning: "
// and the hints as options): a huge condition number, an estimated noise level
// with fewer than kFewResidualDof residual degrees of freedom on an axis
// (hints: the sensor's noise), samples whose residuals are implausible for the
// fitted noise (reported, with the robust fit as hint, or rejected by it), and
// the largest residuals of a streamed log.
std::vector<Warning> identify_warnings(const IdentifySummary& s, const std::string& source);

// What a fit has to say beyond its figures, one line each without a prefix:
// gravity taken from the force (eq. 37; no hints), then identify_warnings
// (report.hpp). Each front end prints a warning's hints its own way.
std::vector<Warning> identification_notes(const IdentifySummary& summary,
                                          const std::string& source);

// The identification as one file (CBOR, matrices as raw little-endian
// doubles: every value bit for bit) for another process on this machine: the
// model by its URDF path (absolute), sensor link and held joints; the base
// parameters by their reduction options (find_base_parameters is
// deterministic); the warnings as {message, hints: [{setting, value}]}, or,
// with `spell`, each as the caller prints it (its hints spelled into the
// message, none kept: the CLI's report lists them as the command printed
// them). read_identification loads the URDF again and checks that the base
// parameters come out the same; InputError naming the file otherwise or for a
// file that is not such a record. It reads warnings stored as strings (older
// records) as messages without hints.
void write_identification(const std::string& path, const Identification& ident,
                          HintSpeller spell = nullptr);
Identification read_identification(const std::string& path);

}  // namespace massid

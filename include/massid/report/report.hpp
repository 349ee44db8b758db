// Human-readable reports of a model, an identification and a prediction: the
// CLI only prints these.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/design/design.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/physical.hpp"

namespace massid {

// Per-axis agreement of predicted with measured wrenches.
struct PredictionErrors {
  Wrench rms = Wrench::Zero();               // RMS of measured - predicted
  Wrench max = Wrench::Zero();               // largest |measured - predicted|
  Wrench range = Wrench::Zero();             // max - min of the measured axis over the file
  Wrench percent_of_range = Wrench::Zero();  // 100 rms / range (inf for a constant axis)
};

// measured, predicted: [N x 6].
PredictionErrors prediction_errors(const Eigen::MatrixXd& measured,
                                   const Eigen::MatrixXd& predicted);

std::string model_report(const Model& model, const BaseParameters& base);

std::string identify_report(const Model& model, const BaseParameters& base,
                            const IdentifySummary& summary, const std::string& data_source);
// The physically consistent parameters (IdentifyOptions::physical): per link
// m, centre of mass, principal moments about it and consistency (J's smallest
// eigenvalue), then the worst base-parameter mismatch in std and the solver's
// figures. `spell` names the setting in the caller's terms (errors.hpp).
std::string physical_report(const BaseParameters& base, const PhysicalSummary& p,
                            HintSpeller spell);
std::string prediction_report(const PredictionErrors& errors, int samples);
// `evaluated` names the evaluated plan's file, empty for a new plan. `spell`
// names the settings the prose mentions (level poses, the clearance) in the
// caller's terms (errors.hpp): the CLI's options, Python's keywords.
std::string design_report(const Model& model, const BaseParameters& base, const DesignSummary& s,
                          const DesignOptions& options, const std::string& evaluated,
                          HintSpeller spell);

}  // namespace massid

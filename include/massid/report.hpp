// Human-readable reports of a model, an identification and a prediction: the
// CLI only prints these.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/design.hpp"
#include "massid/estimation.hpp"
#include "massid/model.hpp"
#include "massid/predictor.hpp"

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
// Warnings about an identification, one line each ("massid: warning: ..."):
// an estimated noise level with fewer than kFewResidualDof residual degrees of
// freedom on an axis, samples whose residuals are implausible for the fitted
// noise (reported, or rejected with --robust), and the largest residuals of a
// streamed log.
std::vector<std::string> identify_warnings(const IdentifySummary& s, const std::string& source);

std::string identify_report(const Model& model, const BaseParameters& base,
                            const IdentifySummary& summary, const std::string& data_source);
std::string prediction_report(const PredictionErrors& errors, int samples);
// `evaluated` names the file for --evaluate, empty for a new plan.
std::string design_report(const Model& model, const BaseParameters& base, const DesignSummary& s,
                          const DesignOptions& options, const std::string& evaluated);

}  // namespace massid

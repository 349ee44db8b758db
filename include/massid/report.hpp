// Human-readable reports of a model, an identification and a prediction: the
// CLI only prints these.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/design.hpp"
#include "massid/errors.hpp"
#include "massid/estimation.hpp"
#include "massid/model.hpp"
#include "massid/physical.hpp"
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

// What a base parameter's std is judged against: its part of the robot's
// gravity wrench at full scale, M L^k for a parameter in kg m^k (k = 0 mass,
// 1 first moment, 2 inertia), with M the identified total mass (else the
// URDF's) and L the robot's reach (kinematics.hpp). A std of 1 % of it moves
// the predicted moments by about 1 % of the largest the robot makes, whatever
// the parameter's own value: a combination that is zero by symmetry is judged
// as well determined as its neighbours. [num_mass]; NaN when M or L is 0.
Eigen::VectorXd parameter_scales(const Model& model, const BaseParameters& base,
                                 const IdentifySummary* summary);
// A parameter is poorly determined when its std exceeds this part of its scale.
constexpr double kPoorStdOfScale = 0.01;
// Warnings about an identification, each message one line starting with the
// source and without a prefix or newline (the CLI prints "massid: warning: "
// and the hints as options): a huge condition number, an estimated noise level
// with fewer than kFewResidualDof residual degrees of freedom on an axis
// (hints: the sensor's noise), samples whose residuals are implausible for the
// fitted noise (reported, with the robust fit as hint, or rejected by it), and
// the largest residuals of a streamed log.
std::vector<Warning> identify_warnings(const IdentifySummary& s, const std::string& source);

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

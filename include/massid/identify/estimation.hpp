// Identification of the base parameters by weighted least squares
// (paper eqs. 32-35, solved by Householder QR instead of eq. 35's normal
// equations), with the covariance of the estimate and the eq. 36 condition number.
//
// Options -> identify() -> IdentifySummary, in the style of Ceres' Solve().
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/delay_estimate.hpp"
#include "massid/identify/physical.hpp"
#include "massid/identify/rest_windows.hpp"

namespace massid {

// Sensor drift (needs the offsets, BaseParameters::offset): the offset moves
// linearly in time (column t), or is separate per block of samples (column
// block: the sensor was re-zeroed between blocks). The offsets reported are
// those at the end of the log (Linear) or of the last block (PerBlock), the
// ones a prediction made afterwards should use.
enum class Drift { None, Linear, PerBlock };

struct IdentifyOptions {
  // Per-axis noise standard deviations. Unset: estimated per axis (fx ... mz)
  // from the residuals, iterating the weighted solve `weight_iterations` times.
  std::optional<double> sigma_force;   // N
  std::optional<double> sigma_moment;  // N m
  int weight_iterations = 4;
  // Rank decision on the column-normalised regressor: a singular value below
  // rank_tolerance * largest marks an undetermined direction.
  double rank_tolerance = 1e-9;
  // Robust estimation: a robust fit (Huber, then Tukey's biweight, on each
  // sample's standardised residual norm with MAD noise scales) finds the
  // samples whose residuals are implausible; they are rejected and the
  // estimate is the weighted least-squares solution of the others. Without it
  // such samples are only reported (IdentifySummary::outliers).
  bool robust = false;
  // Family-wise false-alarm probability of the outlier test over all samples.
  double outlier_probability = 0.01;
  Drift drift = Drift::None;
  // A static log with t recorded while the robot moved from pose to pose:
  // only its rest windows are samples (rest_windows.hpp; identify_file and
  // identify(model, request, source) of identify_request.hpp apply it; identify()
  // takes the samples as given).
  RestWindowOptions rest;
  // Motion logs: the lag of the wrench behind the joints (delay.hpp), s: given,
  // or estimated within +-max_delay (delay_auto). identify_request.hpp applies it.
  std::optional<double> delay;
  bool delay_auto = false;
  double max_delay = 0.02;
  // Physically consistent standard parameters fitted to the identified base
  // parameters (physical.hpp): identify_request.hpp applies it, identify() ignores it.
  std::optional<PhysicalOptions> physical;
};

// A sample whose residual is implausible for the fitted noise.
struct Outlier {
  int sample = 0;      // row in Samples
  int line = 0;        // file line
  double score = 0.0;  // d = sqrt(sum_k (r_k / sigma_k)^2), robust sigma; chi with 6 dof
};

struct IdentifySummary {
  Eigen::VectorXd value;        // [num_unknowns] base parameters, then offsets
  Eigen::VectorXd stddev;       // [num_unknowns] standard deviations
  Eigen::MatrixXd covariance;   // [num_unknowns x num_unknowns]
  double condition_number = 0;  // eq. 36: moment rows over moment unknowns, unscaled (in motion:
                                // every row, columns scaled to unit norm)
  Eigen::Matrix<double, 6, 1> residual_rms;  // fx fy fz mx my mz, unweighted
  Eigen::Matrix<double, 6, 1> residual_max;  // largest |residual| per axis
  Eigen::Matrix<double, 6, 1> sigma;         // noise per axis used as weights
  bool sigma_estimated = true;               // sigma from residuals (else from options)
  bool sigma_force_given = false;            // options.sigma_force was set
  bool sigma_moment_given = false;           // options.sigma_moment was set
  // Degrees of freedom of each axis' residuals: the samples used less the
  // fit's leverages on the axis' rows, N - tr(H_kk) (they sum to 6N - p). An
  // estimated sigma_k is sqrt(SSR_k / residual_dof_k); with few (below
  // kFewResidualDof) it is uncertain and identify_warnings says so. Infinite:
  // not computed (a summary built by hand).
  Eigen::Matrix<double, 6, 1> residual_dof =
      Eigen::Matrix<double, 6, 1>::Constant(std::numeric_limits<double>::infinity());
  double chi2_per_dof = 1.0;  // weighted residual sum / (6N - p)
  int samples = 0;
  bool gravity_from_force = false;
  bool gravity_from_upstream = false;  // gravity from the joints above the sensor link
  // Outlier test (always run): samples with d above outlier_threshold. With
  // options.robust they are rejected (not used in the estimate); else reported.
  std::vector<Outlier> outliers;
  double outlier_threshold = 0.0;
  // False for a streamed fit (streaming.hpp): no per-sample residuals, so the
  // test run was largest_residuals_implausible; outliers is then empty.
  bool per_sample_test = false;
  // Without the robust fit: the rows whose residual lies beyond the noise
  // by the rule of contact (find_contact_episodes, setup_checks.hpp: each axis
  // standardised by the residual's own median and robust scale, so rows that
  // an external wrench drives stand out even where they inflate the fitted
  // noise and hide from the outlier test), with the d they exceed. Filled
  // where the per-sample residuals are at hand (in memory; a streamed static
  // file of at most 64 MB re-read); empty otherwise. Not recorded in files.
  std::vector<Outlier> beyond_noise;
  double beyond_noise_threshold = 0.0;
  bool robust = false;
  // Drift unknowns beyond the base parameters and offsets: names, values, std.
  Drift drift = Drift::None;
  std::vector<std::string> drift_names;
  Eigen::VectorXd drift_value, drift_stddev;
  // The rest windows of a continuous static log (rest.continuous: only their
  // rows are the samples); else not continuous, every row a sample.
  RestWindows rest;
  // Motion logs: the wrench delay applied before the fit (delay.hpp).
  DelayEstimate delay;
};

// Below this many residual degrees of freedom on an axis an estimated noise
// level is not trustworthy: sigma_k is then uncertain by 1/sqrt(2 dof) (22 %
// at 10) and the errors over the reported std follow Student's t with dof
// degrees of freedom, whose rms sqrt(dof / (dof - 2)) is 1.12 at 10 and grows
// fast below (1.29 at 5).
constexpr double kFewResidualDof = 10.0;

// The degrees of freedom an estimated sigma_k divides SSR_k by: the samples
// used less tr(H_kk), floored at 0.5 (near zero the axis is fitted exactly).
double noise_dof(double samples, double leverage);

// Throws IdentifiabilityError when the samples cannot determine every unknown,
// naming them and the poses that would determine them.
// \param[in] samples  q [N x model.num_joints()], gravity [N x 3], wrench
//                     [N x 6]; each optional array (qd, qdd [N x joints], the
//                     upstream ones, sensor_motion [N x 9], line, time, block
//                     [N]) empty or of that shape: else ArgumentError naming it
//                     (no wrench at all: InputError)
IdentifySummary identify(const Model& model, const BaseParameters& base, const Samples& samples,
                         const IdentifyOptions& options = {});

// For a fit without per-sample residuals (streamed): is any axis' largest
// residual above the two-sided normal bound at 1 % over all 6N residuals?
// largest_residual_bound(N) is that bound in sigmas.
double largest_residual_bound(int samples);
bool largest_residuals_implausible(const IdentifySummary& s);

// [N x 6] the wrench the fit ascribes to each sample: Y_b(q_i, g_i) x (eq. 29)
// plus its drift terms; samples.wrench - fitted are the fit's residuals (rejected
// samples included). `samples` must be those the summary was identified from.
Eigen::MatrixXd fitted_wrenches(const Model& model, const BaseParameters& base,
                                const Samples& samples, const IdentifySummary& summary);

// Stacked base regressor, eq. 33: [6N x num_unknowns], rows fx..mz per sample.
Eigen::MatrixXd stacked_regressor(const Model& model, const BaseParameters& base,
                                  const Samples& samples);

// The paper's eq. 36 figure for a stacked regressor A: the condition number of
// its moment rows over the moment unknowns, unscaled. In motion (every row
// involves most unknowns, of different units): scaled_condition_number(A).
double moment_condition_number(const BaseParameters& base, const Eigen::MatrixXd& A);
// The condition number of A with its columns scaled to unit norm.
double scaled_condition_number(const Eigen::MatrixXd& A);

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

}  // namespace massid

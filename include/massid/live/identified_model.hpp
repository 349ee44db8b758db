// One identified model behind every door: the chain params file -> Model ->
// BaseParameters -> values -> predictor, made once, the same for `massid
// predict`, `massid compensate`, `massid emulate`, Python's massid.Predictor
// and the C interface (massid.h).
//
// An IdentifiedModel holds the Model (the URDF loaded at the parameters'
// sensor link with their held joints), the BaseParameters, the values (base
// parameters, then the six offsets when identified), their std and covariance
// where known, the offset, whether the parameters are static (first moments,
// identified at rest) or dynamic (ten per link, identified in motion), and the
// compiled predictor of that kind (Predictor or MotionPredictor). It is
// immutable once made and cheap to copy (copies share it); predicting writes
// a separate workspace, IdentifiedModelData (one per thread), as
// Predictor/PredictorData do.
//
// The offset convention. Every prediction (predict(), predict_motion(), their
// batch forms, and the methods below) is the MECHANISM's wrench on the sensor
// alone, never the sensor offset. The offset enters in one place only:
//
//   sensor_reading(w) = w + offset            what the sensor reads
//   compensate(measured, w) = (measured - w) - offset   what is left (`*_comp`)
//
// with offset zero when none was identified. Every door computes its
// compensated wrench with compensate(), so that they agree to the bit.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/params_file.hpp"

namespace massid {

struct Identification;  // identification.hpp

struct IdentifiedModelOptions {
  // Predict from the params file's "physical" section (identify --physical;
  // K pi_phys and the file's offsets) instead of its base parameters; from an
  // Identification, from its physical fit. InputError when there is none.
  bool physical = false;
};

class IdentifiedModelData;

class IdentifiedModel {
 public:
  // Empty: every prediction throws ArgumentError.
  IdentifiedModel() = default;

  // From a params file: the URDF at urdf_path loaded at the file's sensor
  // link with its held joints, the file's values mapped onto this model's
  // base parameters. InputError naming the file (file:line:column for a
  // malformed params file; params of another robot or sensor link).
  static IdentifiedModel load(const std::string& urdf_path, const std::string& params_path,
                              const IdentifiedModelOptions& options = {});
  static IdentifiedModel load(const std::string& urdf_path, const ParamsFile& params,
                              const IdentifiedModelOptions& options = {});
  // The same for a model already loaded as the file says (load_urdf at
  // params.sensor_link, hold_joints with params.held).
  static IdentifiedModel from_params(Model model, const ParamsFile& params,
                                     const IdentifiedModelOptions& options = {});

  // From an identification in memory (identification.hpp): its model, base
  // parameters, values, std and covariance.
  static IdentifiedModel from_identification(const Identification& ident,
                                             const IdentifiedModelOptions& options = {});

  // From base parameters and their values (num_unknowns: the base
  // parameters, then the six offsets when base.offset); std and covariance
  // optional (empty: unknown). A motion base (base.motion()) is dynamic.
  // `source` names the parameters in messages.
  static IdentifiedModel from_values(Model model, BaseParameters base, Eigen::VectorXd values,
                                     Eigen::VectorXd stddev = {}, Eigen::MatrixXd covariance = {},
                                     std::string source = "the parameters");

  // The same model with the wrench's clock delay, s (delay.hpp: positive when
  // the wrench arrives late): predict_log and the Compensator predict row i
  // for the joint stream at t_i - delay. from_params takes the file's
  // "delay", from_identification the delay the fit applied.
  IdentifiedModel with_delay(double seconds) const;
  // The same model with the fit's residual RMS per axis (N, N m; zero:
  // unknown), the tracker's default sensor noise (tracker_noise).
  // from_params takes the file's "residual_rms", from_identification its
  // summary's.
  IdentifiedModel with_residual_rms(const Wrench& rms) const;

  bool empty() const { return !impl_; }
  const Model& model() const;
  const BaseParameters& base() const;
  const Eigen::VectorXd& values() const;      // [num_unknowns] base parameters, then offsets
  const Eigen::VectorXd& stddev() const;      // [num_unknowns], empty when unknown
  const Eigen::MatrixXd& covariance() const;  // [num_unknowns^2], empty when unknown
  const std::string& source() const;          // the params file's path, for messages
  int num_joints() const;
  bool dynamic() const;        // identified in motion: predicts the full wrench
  bool has_offset() const;     // the sensor offsets were identified
  bool sensor_moving() const;  // dynamic, identified with the sensor frame moving
  // Dynamic, identified at one gravity (a level platform): that gravity
  // (sensor frame); nullopt otherwise.
  std::optional<Eigen::Vector3d> fixed_gravity() const;
  const Wrench& offset() const;        // f_0, m_0; zero without offsets
  double delay() const;                // the clock delay, s; 0 without
  const Wrench& residual_rms() const;  // the fit's, per axis; zero when unknown

  // The compiled predictor of the model's kind (the other: ArgumentError).
  const Predictor& predictor() const;               // static
  const MotionPredictor& motion_predictor() const;  // dynamic

  // THE offset convention (header): the sensor's reading of a predicted
  // mechanism wrench, and the compensated wrench of a measurement.
  Wrench sensor_reading(const Wrench& predicted) const { return predicted + offset(); }
  Wrench compensate(const Wrench& measured, const Wrench& predicted) const {
    return (measured - predicted) - offset();
  }
  // [N x 6] row by row as the single forms: predicted + offset, and
  // (measured - predicted) - offset.
  Eigen::MatrixXd sensor_reading_rows(const Eigen::Ref<const Eigen::MatrixXd>& predicted) const;
  Eigen::MatrixXd compensate_rows(const Eigen::Ref<const Eigen::MatrixXd>& measured,
                                  const Eigen::Ref<const Eigen::MatrixXd>& predicted) const;

  // The mechanism's gravity wrench at rest (no offset), static and dynamic
  // alike: static parameters through the static predictor, dynamic ones
  // through the motion predictor at zero joint velocity and acceleration with
  // the sensor at rest (which is exactly the weight). q: num_joints values.
  Wrench predict_gravity(IdentifiedModelData& data, const double* q,
                         const Eigen::Vector3d& g) const;
  Wrench predict_gravity(IdentifiedModelData& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                         const Eigen::Vector3d& g) const;

  // The mechanism's wrench (no offset): dynamic parameters, weight and motion
  // (qd, qdd: num_joints values each; sensor: the sensor frame's motion);
  // static ones, the gravity wrench (qd, qdd and sensor not read).
  Wrench predict(IdentifiedModelData& data, const double* q, const double* qd, const double* qdd,
                 const Eigen::Vector3d& g, const FrameMotion& sensor = {}) const;

  // [N x 6] the mechanism's wrench at every sample (no offset), as `massid
  // predict` writes fx_pred..mz_pred: static, from q and gravity; dynamic,
  // from q, qd, qdd (zero where the samples have none), gravity and, where
  // the samples have it, the sensor's motion.
  Eigen::MatrixXd predict_samples(IdentifiedModelData& data, const Samples& samples) const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
  const Impl& checked(const char* function) const;
};

// The workspace of an IdentifiedModel's predictions: sized once, reused by
// every call without allocating (except predict_samples' result).
class IdentifiedModelData {
 public:
  explicit IdentifiedModelData(const IdentifiedModel& model);

 private:
  friend class IdentifiedModel;
  std::optional<PredictorData> rest;
  std::optional<MotionPredictorData> motion;
  std::vector<double> zeros;  // [max(1, num_joints)] qd = qdd = 0 for predict_gravity
};

}  // namespace massid

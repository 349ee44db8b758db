// Predicting a log: the one pipeline behind `massid predict`, Python's
// massid.predict_log and Predictor.predict_log. From a table of samples (a
// plan or a measured log) and an identified model (identified_model.hpp):
//
//   1. the samples of the table's columns (read_samples.hpp);
//   2. the set-up checks of the file (setup_checks.hpp: joint units and
//      columns, gravity, and the wrench's signs, frame and units when it has
//      one): a refusing verdict throws SetupRefused;
//   3. a model with a clock delay (IdentifiedModel::delay, identify --delay):
//      row i takes the joint stream at t_i - delay (delay_wrench, delay.hpp;
//      rows whose instant lies before the log's start take its first row's),
//      so that P_i is the wrench the sensor logs at row i; InputError without t;
//   4. a dynamic model's log without JOINT_vel/_acc: the velocities and
//      accelerations derived from t by the zero-phase low-pass
//      (motion_data.hpp), every filtered row kept (no decimation), the rows it
//      drops at each end of each block left out;
//   5. per row i the mechanism's wrench, never the offset (eq. 29 at rest,
//      Newton-Euler over the identified bodies in motion):
//
//        P_i = predictor(q_i[, qd_i, qdd_i], g_i)                    N, N m
//
//   6. with a measured wrench w_i, the compensated wrench and the contact
//      episodes of the residual against what the sensor reads:
//
//        C_i = (w_i - P_i) - offset            (the *_comp columns)
//        r_i = w_i - (P_i + offset)            (find_contact_episodes)
//
// Every door prints or returns these; none repeats the steps.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "massid/core/samples.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/csv.hpp"
#include "massid/live/identified_model.hpp"

namespace massid {

struct PredictLogOptions {
  // samples: the root gravity (a sensor below movable joints) and the column
  // names (its sensor_motion is set by the model: dynamic or not); filter: the
  // cut-off of a dynamic model's log without _vel/_acc (0: min(10, rate/20)).
  // The filter's decimation is not used: every filtered row is predicted.
  MotionDataOptions motion;
  // The set-up checks (off: the file is predicted as it is, no verdict).
  bool checks = true;
  // The grouping of rows beyond the noise into contact episodes.
  ContactOptions contact;
  // Called with the verdict as soon as it is made, before a refusal is thrown
  // and before the prediction: a door that prints the verdict does it there,
  // so that its lines come before any later error. May be empty.
  std::function<void(const SetupVerdict&)> on_verdict;
};

struct LogPrediction {
  std::string source;  // the log's name in messages and notes
  // The samples predicted, N rows: every row of the table, or those the
  // motion filter keeps (samples.line: their file lines).
  Samples samples;
  // The table's rows of those samples, in order (the table to write back with
  // *_pred and *_comp columns).
  CsvTable table;
  Eigen::MatrixXd predicted;    // (dim N x 6) P: the mechanism's wrench, *_pred
  Eigen::MatrixXd compensated;  // (dim N x 6) C: *_comp; 0 x 0 without a measured wrench
  SetupVerdict setup;           // the checks' warnings (none refuses); empty without checks
  MotionDataReport motion;      // motion.derived: qd, qdd derived by the filter (its kernels)
  std::vector<ContactEpisode> contact;  // rows carrying an external wrench, in order
  // The delay applied (when the model has one), then contact_note(source, e)
  // per episode.
  std::vector<std::string> notes;
  std::string column_note;  // column_note (read_samples.hpp) on the header, or ""

  bool has_wrench() const { return samples.has_wrench(); }
};

// The steps above. `table`: the log as read_csv (or parse_csv) gives it;
// `source` names it in the notes (the path given by the user). Throws
// SetupRefused (an InputError, the message the CLI prints) for a refusing
// verdict, InputError for a table read_samples or the motion filter refuses.
//
// \param[in] identified  the model, its base parameters, values and offset
// \param[in] table       (dim rows x columns) joints (rad or m, or JOINT_deg),
//                        gravity gx,gy,gz (m/s^2, sensor frame) or its sources,
//                        optionally fx..mz (N, N m); dynamic: JOINT_vel,
//                        JOINT_acc or t (s)
// \param[in] source      the log's name in notes
// \param[in] options     motion options, checks, contact rule
LogPrediction predict_log(const IdentifiedModel& identified, CsvTable table,
                          const std::string& source, const PredictLogOptions& options = {});

}  // namespace massid

// The identified model (identified_model.hpp): made from an identification
// in memory and from the params file written from it, it predicts the same
// bits; its predictions never hold the offset, compensate() and
// sensor_reading() apply it; static and dynamic parameters alike.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/identify/predict_log.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "massid/live/identified_model.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

namespace fs = std::filesystem;

const std::string kPuma = MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf";
const std::string kUr = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";

Wrench test_offset() {
  Wrench o;
  o << 1.5, -2.0, 0.5, 0.1, -0.2, 0.05;
  return o;
}

// Random samples: q within the joints' range, gravity of |g| in random
// directions, and in motion random rates (each row its own pose: the
// regressor needs no trajectory).
Samples random_samples(const Model& model, int n, bool motion, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> z;
  const int nj = model.num_joints();
  Samples s;
  s.source = "random";
  s.q.resize(n, nj);
  s.gravity.resize(n, 3);
  if (motion) {
    s.qd.resize(n, nj);
    s.qdd.resize(n, nj);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < nj; ++j) {
      s.q(i, j) = model.joints[j].generic_position(u(rng));
      if (motion) {
        s.qd(i, j) = 2.0 * z(rng);
        s.qdd(i, j) = 5.0 * z(rng);
      }
    }
    const Eigen::Vector3d g(z(rng), z(rng), z(rng) - 3.0);
    s.gravity.row(i) = (kStandardGravity * g.normalized()).transpose();
  }
  s.line.resize(n);
  for (int i = 0; i < n; ++i) s.line[i] = i + 2;
  return s;
}

// An identification with offsets from noisy simulated data, as identify_log
// keeps it: the model, the base parameters and the fit.
Identification identification_of(const Model& model, bool motion) {
  Samples s = random_samples(model, motion ? 400 : 60, motion, 5);
  SimulateOptions o;
  o.dynamic = motion;
  o.offset = test_offset();
  o.noise_force = 0.05;
  o.noise_moment = 0.005;
  o.seed = 3;
  s.wrench = simulate_wrenches(model, s, o);
  Identification ident;
  ident.model = model;
  BaseParameterOptions bo = motion ? motion_base_options(s, true) : BaseParameterOptions{};
  bo.offset = true;
  ident.base = find_base_parameters(model, bo);
  ident.summary = identify(model, ident.base, s);
  ident.samples = std::move(s);
  return ident;
}

class IdentifiedModelTest : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("massid_idmodel_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + std::to_string(GetParam()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// From memory and from the params file written from it (params_json, as
// identify -o writes it): the same values, offset and predictions to the bit.
TEST_P(IdentifiedModelTest, FromAParamsFileAndFromMemoryPredictTheSameBits) {
  const bool motion = GetParam();
  const std::string urdf = motion ? kUr : kPuma;
  const Identification ident = identification_of(load_urdf(urdf), motion);
  const std::string path = (dir_ / "params.json").string();
  std::ofstream(path) << params_json(ident.model, ident.base, &ident.summary);

  const IdentifiedModel memory = IdentifiedModel::from_identification(ident);
  const IdentifiedModel file = IdentifiedModel::load(urdf, path);
  ASSERT_EQ(memory.dynamic(), motion);
  ASSERT_EQ(file.dynamic(), motion);
  EXPECT_TRUE(file.has_offset());
  EXPECT_EQ(file.source(), path);
  ASSERT_EQ(file.values().size(), memory.values().size());
  for (Eigen::Index i = 0; i < file.values().size(); ++i)
    EXPECT_EQ(file.values()[i], memory.values()[i]) << ident.base.unknown_name(static_cast<int>(i));
  EXPECT_EQ(file.offset(), memory.offset());
  EXPECT_EQ(memory.offset(), ident.summary.value.tail<6>());
  // The file's std is the fit's.
  ASSERT_EQ(file.stddev().size(), ident.summary.stddev.size());
  for (Eigen::Index i = 0; i < file.stddev().size(); ++i)
    EXPECT_EQ(file.stddev()[i], ident.summary.stddev[i]);
  EXPECT_EQ(memory.covariance().rows(), ident.base.num_unknowns());
  // The fit's residual RMS per axis travels with the model (the tracker's
  // default noise, tracker_noise): read back from the file as it was written.
  EXPECT_EQ(memory.residual_rms(), ident.summary.residual_rms);
  EXPECT_EQ(file.residual_rms(), memory.residual_rms());
  EXPECT_GT(file.residual_rms().minCoeff(), 0.0);

  // Fresh poses (another seed): the same bits through every prediction.
  const Samples fresh = random_samples(ident.model, 50, motion, 77);
  IdentifiedModelData dm(memory), df(file);
  const Eigen::MatrixXd Pm = memory.predict_samples(dm, fresh);
  const Eigen::MatrixXd Pf = file.predict_samples(df, fresh);
  EXPECT_TRUE((Pm.array() == Pf.array()).all()) << (Pm - Pf).cwiseAbs().maxCoeff();
  for (int i = 0; i < fresh.size(); ++i) {
    const Eigen::VectorXd q = fresh.q.row(i).transpose();
    const Eigen::Vector3d g = fresh.gravity.row(i).transpose();
    const Wrench gm = memory.predict_gravity(dm, q, g), gf = file.predict_gravity(df, q, g);
    EXPECT_EQ(gm, gf) << "row " << i;
    // The batch form and the single form agree to the bit.
    if (motion) {
      const Eigen::VectorXd qd = fresh.qd.row(i).transpose(), qdd = fresh.qdd.row(i).transpose();
      EXPECT_EQ(file.predict(df, q.data(), qd.data(), qdd.data(), g), Wrench(Pf.row(i).transpose()))
          << "row " << i;
    } else {
      EXPECT_EQ(gf, Wrench(Pf.row(i).transpose())) << "row " << i;
    }
  }
}

// The predictions are the mechanism's wrench alone: against the URDF's own
// (simulate, no offset), the identified prediction is close, and the
// compensated measurement (measured - predicted - offset) of data with the
// offset is the noise; sensor_reading adds the offset back.
TEST_P(IdentifiedModelTest, PredictionsHoldNoOffsetAndCompensateSubtractsIt) {
  const bool motion = GetParam();
  const Model model = load_urdf(motion ? kUr : kPuma);
  const IdentifiedModel identified =
      IdentifiedModel::from_identification(identification_of(model, motion));
  Samples fresh = random_samples(model, 40, motion, 99);
  SimulateOptions exact;
  exact.dynamic = motion;
  const Eigen::MatrixXd truth = simulate_wrenches(model, fresh, exact);
  IdentifiedModelData data(identified);
  const Eigen::MatrixXd P = identified.predict_samples(data, fresh);
  const double scale = truth.cwiseAbs().maxCoeff();
  EXPECT_LT((P - truth).cwiseAbs().maxCoeff(), 0.01 * scale);
  // Measured with the offset: compensates to about zero (the fit's error).
  Eigen::MatrixXd measured = truth;
  measured.rowwise() += test_offset().transpose();
  const Eigen::MatrixXd C = identified.compensate_rows(measured, P);
  EXPECT_LT(C.cwiseAbs().maxCoeff(), 0.01 * scale);
  // Without subtracting the offset, the force residual would be the offset.
  EXPECT_GT((measured - P).col(1).cwiseAbs().minCoeff(), 1.0);
  for (int i = 0; i < fresh.size(); ++i) {
    const Wrench p = P.row(i).transpose(), m = measured.row(i).transpose();
    EXPECT_EQ(identified.compensate(m, p), Wrench(C.row(i).transpose()));
    EXPECT_EQ(identified.sensor_reading(p), Wrench(p + identified.offset()));
  }
  EXPECT_TRUE((identified.sensor_reading_rows(P).array() ==
               (P.rowwise() + identified.offset().transpose()).array())
                  .all());
}

// The gravity-only prediction of dynamic parameters is the motion predictor
// at rest: the same bits as predict() with zero rates, and the URDF's static
// wrench (a static fit of the same robot agrees with it).
TEST(IdentifiedModel, GravityOnlyPredictionOfADynamicFitIsItsWeight) {
  const Model model = load_urdf(kUr);
  const IdentifiedModel dynamic =
      IdentifiedModel::from_identification(identification_of(model, true));
  const IdentifiedModel rest =
      IdentifiedModel::from_identification(identification_of(model, false));
  const Samples fresh = random_samples(model, 30, false, 4);
  const Eigen::MatrixXd truth = simulate_wrenches(model, fresh);
  IdentifiedModelData dd(dynamic), dr(rest);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_joints());
  for (int i = 0; i < fresh.size(); ++i) {
    const Eigen::VectorXd q = fresh.q.row(i).transpose();
    const Eigen::Vector3d g = fresh.gravity.row(i).transpose();
    const Wrench w = dynamic.predict_gravity(dd, q, g);
    EXPECT_EQ(w, dynamic.predict(dd, q.data(), zero.data(), zero.data(), g));
    const Wrench t = truth.row(i).transpose();
    EXPECT_LT((w - t).norm(), 0.01 * t.norm()) << i;
    EXPECT_LT((w - rest.predict_gravity(dr, q, g)).norm(), 0.01 * t.norm()) << i;
  }
}

// Params of another robot, and an empty model: errors that say so.
TEST(IdentifiedModel, ParamsOfAnotherRobotAndAnEmptyModelAreErrors) {
  const Identification ident = identification_of(load_urdf(kPuma), false);
  const fs::path path = fs::temp_directory_path() / "massid_idmodel_other.json";
  std::ofstream(path) << params_json(ident.model, ident.base, &ident.summary);
  EXPECT_THROW((void)IdentifiedModel::load(kUr, path.string()), InputError);
  // The right robot at another sensor link: the file named.
  ParamsFile params = read_params(path.string());
  const Model other = load_urdf(kUr);
  try {
    (void)IdentifiedModel::from_params(other, params);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  fs::remove(path);
  // A file whose base parameters are gone (a fuzzer's find: the factorisation
  // of an empty matrix asserted in Eigen): named, an InputError.
  ParamsFile none = params;
  none.base_parameters.clear();
  const Model puma = load_urdf(kPuma);
  try {
    (void)IdentifiedModel::from_params(puma, none);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no base parameters"), std::string::npos) << e.what();
  }
  const IdentifiedModel empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_THROW((void)empty.offset(), ArgumentError);
  EXPECT_THROW(IdentifiedModelData{empty}, ArgumentError);
  EXPECT_THROW((void)IdentifiedModel::from_identification(ident).motion_predictor(), ArgumentError);
}

// A log of `samples` as CSV text: joints, gx,gy,gz, fx..mz (header on line 1).
std::string csv_text(const Model& model, const Samples& s) {
  std::string text;
  for (const Joint& j : model.joints) text += j.name + ",";
  text += "gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < s.size(); ++i) {
    for (int j = 0; j < model.num_joints(); ++j) text += format_number(s.q(i, j)) + ",";
    for (int k = 0; k < 3; ++k) text += format_number(s.gravity(i, k)) + ",";
    for (int k = 0; k < 6; ++k) text += format_number(s.wrench(i, k)) + (k < 5 ? "," : "\n");
  }
  return text;
}

// predict_log is the steps it names, done once: the identified model's
// prediction and compensation of the table's samples, and the contact
// episodes of the planted rows with their notes.
TEST(PredictLog, PredictsCompensatesAndNamesThePlantedContact) {
  const Model model = load_urdf(kPuma);
  const IdentifiedModel identified =
      IdentifiedModel::from_identification(identification_of(model, false));
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/holdout.csv");
  ASSERT_EQ(s.size(), 200);
  SimulateOptions o;
  o.offset = test_offset();
  o.noise_force = 0.05;
  o.noise_moment = 0.005;
  o.seed = 4;
  s.wrench = simulate_wrenches(model, s, o);
  const Wrench contact = (Wrench() << 12.0, -8.0, 15.0, 0.5, -0.3, 0.2).finished();
  for (int i = 50; i < 80; ++i) s.wrench.row(i) += contact.transpose();
  const CsvTable table = parse_csv(csv_text(model, s), "log.csv");

  int verdicts = 0;
  PredictLogOptions po;
  po.on_verdict = [&](const SetupVerdict& v) {
    ++verdicts;
    EXPECT_FALSE(v.refused());
  };
  const LogPrediction p = predict_log(identified, table, "log.csv", po);
  EXPECT_EQ(verdicts, 1);
  EXPECT_TRUE(p.setup.findings.empty());
  EXPECT_FALSE(p.motion.derived);
  const Samples read = read_samples(model, table, WrenchColumns::Optional);
  IdentifiedModelData data(identified);
  const Eigen::MatrixXd P = identified.predict_samples(data, read);
  EXPECT_EQ(p.predicted, P);
  EXPECT_EQ(p.compensated, identified.compensate_rows(read.wrench, P));
  EXPECT_EQ(p.samples.line, table.line);
  EXPECT_EQ(p.table.rows, table.rows);
  ASSERT_EQ(p.contact.size(), 1u);
  EXPECT_EQ(p.contact[0].first_line, 52);  // rows 50..79, the header on line 1
  EXPECT_EQ(p.contact[0].last_line, 81);
  EXPECT_NEAR(p.contact[0].force, contact.head<3>().norm(), 0.3);
  EXPECT_EQ(p.notes, std::vector<std::string>{contact_note("log.csv", p.contact[0])});
  // The stream form (compensate): the same episodes from the lines and the
  // measured wrench's RMS.
  const Eigen::MatrixXd residual = read.wrench - identified.sensor_reading_rows(P);
  const Eigen::Vector2d rms(std::sqrt(read.wrench.leftCols<3>().rowwise().squaredNorm().mean()),
                            std::sqrt(read.wrench.rightCols<3>().rowwise().squaredNorm().mean()));
  const std::vector<ContactEpisode> streamed = find_contact_episodes(read.line, residual, rms);
  ASSERT_EQ(streamed.size(), 1u);
  EXPECT_EQ(contact_note("log.csv", streamed[0]), p.notes[0]);
}

// A refusing verdict: SetupRefused with the checks' errors (the message one
// error's, as the CLI prints it), after on_verdict saw it; without the
// checks the log is predicted as it is.
TEST(PredictLog, RefusesANegatedChannelWithTheChecksMessage) {
  const Model model = load_urdf(kPuma);
  const IdentifiedModel identified =
      IdentifiedModel::from_identification(identification_of(model, false));
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/holdout.csv");
  SimulateOptions o;
  o.offset = test_offset();
  o.noise_force = 0.05;
  o.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, o);
  s.wrench.col(2) *= -1.0;  // fz negated
  const CsvTable table = parse_csv(csv_text(model, s), "neg.csv");
  const SetupVerdict verdict = check_input_setup(
      model, read_samples(model, table, WrenchColumns::Optional), table.header, false);
  ASSERT_TRUE(verdict.refused());
  ASSERT_EQ(verdict.shown().size(), 1u);
  int verdicts = 0;
  PredictLogOptions po;
  po.on_verdict = [&](const SetupVerdict& v) {
    ++verdicts;
    EXPECT_TRUE(v.refused());
  };
  try {
    (void)predict_log(identified, table, "neg.csv", po);
    ADD_FAILURE() << "no error";
  } catch (const SetupRefused& e) {
    EXPECT_EQ(std::string(e.what()), verdict.shown()[0].message);
    EXPECT_EQ(e.hints(), verdict.shown()[0].hints);
    EXPECT_NE(std::string(e.what()).find("'fz' is negated"), std::string::npos) << e.what();
    ASSERT_EQ(e.errors().size(), 1u);
    EXPECT_EQ(e.errors()[0].code, verdict.shown()[0].code);
  }
  EXPECT_EQ(verdicts, 1);
  po.checks = false;
  po.on_verdict = nullptr;
  const LogPrediction p = predict_log(identified, table, "neg.csv", po);
  EXPECT_EQ(p.predicted.rows(), 200);
  EXPECT_TRUE(p.setup.findings.empty());
}

INSTANTIATE_TEST_SUITE_P(StaticAndDynamic, IdentifiedModelTest, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Dynamic" : "Static"; });

}  // namespace
}  // namespace massid

namespace massid {
namespace {

// A static fit given a stream with velocity columns compensates the weight
// only, and says so once: for a base sensor (the joints below it move) and
// for a wrist (the joints above it move; before, the note looked only at the
// first joint below the sensor, and a wrist with none said nothing).
TEST(CompensatorNotes, StaticFitOnAMovingStreamSaysTheMotionIsNotCompensatedForAWristToo) {
  const std::string ur = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";
  for (const std::string sensor : {"sensor", "wrist_3_link"}) {
    const Model model = load_urdf(ur, sensor);
    const BaseParameters base = find_base_parameters(model);
    const IdentifiedModel im = IdentifiedModel::from_values(
        model, base, Eigen::VectorXd::Zero(base.num_unknowns()), {}, {}, "params.json");
    std::string header;
    for (const auto* joints : {&model.joints, &model.upstream_joints})
      for (const Joint& j : *joints) header += j.name + "," + j.name + "_vel," + j.name + "_acc,";
    if (model.upstream_joints.empty()) header += "gx,gy,gz,";
    header += "fx,fy,fz,mx,my,mz";
    const Compensator c(im, header, "stdin");
    EXPECT_NE(c.note().find("params.json is a static fit: the weight is compensated, not the "
                            "inertial forces of the motion"),
              std::string::npos)
        << sensor << ": " << c.note();
    // Without velocity columns there is nothing to say.
    std::string still;
    for (const auto* joints : {&model.joints, &model.upstream_joints})
      for (const Joint& j : *joints) still += j.name + ",";
    if (model.upstream_joints.empty()) still += "gx,gy,gz,";
    still += "fx,fy,fz,mx,my,mz";
    EXPECT_EQ(Compensator(im, still, "stdin").note().find("static fit"), std::string::npos)
        << sensor;
  }
}

}  // namespace
}  // namespace massid

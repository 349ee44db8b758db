// Clock alignment (delay.hpp): a 1 kHz motion log whose wrench arrives late
// (the wrench logged at t was the mechanism's at t - delay, simulated from the
// trajectory evaluated there) gives its delay back within 0.2 ms, and the fit
// with it applied matches the URDF's base parameters as a log without lag
// does; a known delay applied gives the same; a lag beyond the scan is named.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/delay.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/predict_log.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/compensator.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kLevel;

// The trajectory at 1 kHz with the wrench of the state `lag` earlier.
Samples lagged_log(const Model& model, double lag, std::uint64_t seed, double duration = 4.0,
                   bool noise = true) {
  const FourierTrajectory tr = random_fourier_trajectory(model, 4, 4.0, seed);
  Samples log = sample_trajectory(tr, duration, 1000.0, kLevel);
  Samples earlier = log;
  for (int i = 0; i < log.size(); ++i) {
    Eigen::VectorXd q(model.num_joints()), qd(model.num_joints()), qdd(model.num_joints());
    tr.evaluate(log.time[i] - lag, q, qd, qdd);
    earlier.q.row(i) = q.transpose();
    earlier.qd.row(i) = qd.transpose();
    earlier.qdd.row(i) = qdd.transpose();
  }
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = noise ? 0.1 : 0.0;
  so.noise_moment = noise ? 0.01 : 0.0;
  so.seed = seed;
  log.wrench = simulate_wrenches(model, earlier, so);
  return log;
}

IdentifySummary fit_of(const Model& model, const Samples& raw, const IdentifyOptions& o,
                       DelayEstimate* d, BaseParameters* base) {
  const Samples s = aligned_motion_samples(model, raw, false, o, {}, d);
  *base = find_base_parameters(model, motion_base_options(s, false));
  return identify(model, *base, s, o);
}

TEST(Delay, TheJointStreamIsMovedExactlyForALinearSignal) {
  Samples raw;
  raw.source = "lin";
  raw.time = Eigen::VectorXd::LinSpaced(50, 0.0, 0.049);
  raw.q.resize(50, 2);
  raw.gravity.resize(50, 3);
  raw.wrench = Eigen::MatrixXd::Random(50, 6);
  for (int i = 0; i < 50; ++i) {
    raw.q.row(i) << 2.0 * raw.time[i], -raw.time[i] + 1;
    raw.gravity.row(i) << raw.time[i], 0.0, -9.8;
  }
  const Samples s = delay_wrench(raw, 0.0013, 3);
  ASSERT_EQ(s.q.rows(), 44);
  EXPECT_EQ(s.time[0], raw.time[3]);
  EXPECT_EQ(s.wrench, raw.wrench.middleRows(3, 44));  // the wrench and its noise untouched
  for (int i = 0; i < s.q.rows(); ++i) {
    const double t = s.time[i] - 0.0013;
    EXPECT_NEAR(s.q(i, 0), 2.0 * t, 1e-12);
    EXPECT_NEAR(s.q(i, 1), -t + 1, 1e-12);
    EXPECT_NEAR(s.gravity(i, 0), t, 1e-12);
  }
  Samples untimed = raw;
  untimed.time.resize(0);
  EXPECT_THROW(delay_wrench(untimed, 0.001, 3), InputError);
}

TEST(Delay, OneMillisecondLagIsFoundAndTheFitIsAsGoodAsWithoutLag) {
  const Model model = load_urdf(test::examples()[1].urdf);  // ur_like
  for (const double lag : {0.001, -0.0023}) {
    SCOPED_TRACE(lag);
    const Samples raw = lagged_log(model, lag, 5);
    IdentifyOptions o;
    o.delay_auto = true;
    DelayEstimate d;
    BaseParameters base;
    const IdentifySummary fit = fit_of(model, raw, o, &d, &base);
    ASSERT_TRUE(d.applied && d.estimated);
    EXPECT_NEAR(d.value, lag, 2e-4);
    EXPECT_GT(d.std, 0.0);
    EXPECT_LT(d.std, 2e-4);
    EXPECT_LT(std::abs(d.value - lag), 4 * d.std + 2e-5);  // the std is honest
    EXPECT_GE(d.scan.size(), 17u);
    EXPECT_LT(test::worst_normalised_error(model, base, fit), 4.5);

    // The lag ignored: the fit is off by far more than its std.
    IdentifyOptions plain;
    DelayEstimate none;
    BaseParameters base0;
    const IdentifySummary ignored = fit_of(model, raw, plain, &none, &base0);
    EXPECT_FALSE(none.applied);
    EXPECT_GT(test::worst_normalised_error(model, base0, ignored),
              3 * test::worst_normalised_error(model, base, fit));

    // The lag given: the same as estimated, to what the estimate's error moves.
    IdentifyOptions given;
    given.delay = lag;
    DelayEstimate g;
    BaseParameters base1;
    const IdentifySummary known = fit_of(model, raw, given, &g, &base1);
    EXPECT_TRUE(g.applied && !g.estimated);
    EXPECT_EQ(g.value, lag);
    EXPECT_LT(test::worst_normalised_error(model, base1, known), 4.5);
  }
}

TEST(Delay, ALagBeyondTheScanIsNamed) {
  const Model model = load_urdf(test::examples()[1].urdf);
  const Samples raw = lagged_log(model, 0.012, 6, 2.0);
  try {
    estimate_delay(model, raw, false, {}, {}, 0.005);
    ADD_FAILURE() << "a 12 ms lag was found within +-5 ms";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond the +-5 ms scanned"), std::string::npos)
        << e.what();
  }
}

// A motion log as CSV text: t, joints, _vel, _acc, gx,gy,gz, fx..mz.
std::string motion_csv(const Model& model, const Samples& s) {
  std::string text = "t,";
  for (const char* suffix : {"", "_vel", "_acc"})
    for (const Joint& j : model.joints) text += j.name + suffix + ",";
  text += "gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < s.size(); ++i) {
    text += format_number(s.time[i]) + ",";
    for (const Eigen::MatrixXd* m : {&s.q, &s.qd, &s.qdd})
      for (int j = 0; j < model.num_joints(); ++j) text += format_number((*m)(i, j)) + ",";
    for (int k = 0; k < 3; ++k) text += format_number(s.gravity(i, k)) + ",";
    for (int k = 0; k < 6; ++k) text += format_number(s.wrench(i, k)) + (k < 5 ? "," : "\n");
  }
  return text;
}

double force_rms(const Eigen::MatrixXd& w, int from) {
  return std::sqrt(w.bottomRows(w.rows() - from).leftCols<3>().rowwise().squaredNorm().mean());
}

// The delay identify found is applied where the model is used (issue 27):
// predict_log on a noise-free log with the same lag leaves only the fit's
// parameter error in *_comp, where the same model without the delay leaves
// the lag's error many times over; the Compensator gives predict_log's
// compensated wrench bit for bit, line by line; and it says what it needs.
TEST(Delay, PredictAndCompensateApplyTheIdentifiedDelay) {
  const Model model = load_urdf(test::examples()[1].urdf);  // ur_like
  const double lag = 0.004;
  IdentifyRequest request;
  request.dynamic = true;
  request.delay = "auto";
  const Identification ident =
      identify(model, request, IdentifySource::data(lagged_log(model, lag, 7)));
  const IdentifiedModel delayed = IdentifiedModel::from_identification(ident);
  EXPECT_EQ(delayed.delay(), ident.summary.delay.value);
  EXPECT_NEAR(delayed.delay(), lag, 2e-4);

  const Samples check = lagged_log(model, lag, 8, 3.0, false);
  const CsvTable table = parse_csv(motion_csv(model, check), "check.csv");
  PredictLogOptions po;
  po.checks = false;
  const LogPrediction with = predict_log(delayed, table, "check.csv", po);
  const LogPrediction without = predict_log(delayed.with_delay(0.0), table, "check.csv", po);
  ASSERT_EQ(with.compensated.rows(), check.size());
  const int settled = 10;  // rows past the delay from the log's start
  EXPECT_LT(force_rms(with.compensated, settled), 0.2 * force_rms(without.compensated, settled));
  ASSERT_FALSE(with.notes.empty());
  EXPECT_NE(with.notes[0].find("clock delay of"), std::string::npos) << with.notes[0];

  // Live, line by line: the same figures.
  std::string header = table.header[0];
  for (std::size_t c = 1; c < table.header.size(); ++c) header += "," + table.header[c];
  Compensator live(delayed, header + "\n", "stdin");
  EXPECT_NE(live.note().find("clock delay"), std::string::npos);
  for (int r = 0; r < table.num_rows(); ++r) {
    std::string line = table.rows[r][0];
    for (std::size_t c = 1; c < table.rows[r].size(); ++c) line += "," + table.rows[r][c];
    live.compensate(line, r + 2);
    ASSERT_EQ(live.compensated(), with.compensated.row(r).transpose()) << "row " << r;
  }
  // The delay interpolates in t: a line whose t does not increase is refused.
  std::string last = table.rows.back()[0];
  for (std::size_t c = 1; c < table.rows.back().size(); ++c) last += "," + table.rows.back()[c];
  try {
    live.compensate(last, table.num_rows() + 2);
    ADD_FAILURE() << "a repeated t was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(fmt::format("stdin:{}: t = ", table.num_rows() + 2), 0), 0u) << what;
    EXPECT_NE(what.find("does not increase (the previous line's is "), std::string::npos) << what;
    EXPECT_NE(what.find("): the clock delay needs time in order"), std::string::npos) << what;
  }

  // Lines 7 ms apart, then 1 ms apart, with a 12 ms delay: the ring of the
  // lines kept grows while its oldest line is anywhere in it; still
  // predict_log's figures on the same lines, bit for bit.
  const IdentifiedModel longer = delayed.with_delay(0.012);
  std::string text = header + "\n";
  for (int r = 0; r < table.num_rows(); r += r < 300 ? 7 : 1) {
    text += table.rows[r][0];
    for (std::size_t c = 1; c < table.rows[r].size(); ++c) text += "," + table.rows[r][c];
    text += "\n";
  }
  const CsvTable uneven = parse_csv(text, "uneven.csv");
  const LogPrediction expected = predict_log(longer, uneven, "uneven.csv", po);
  Compensator grown(longer, header + "\n", "stdin");
  for (int r = 0; r < uneven.num_rows(); ++r) {
    std::string line = uneven.rows[r][0];
    for (std::size_t c = 1; c < uneven.rows[r].size(); ++c) line += "," + uneven.rows[r][c];
    grown.compensate(line, r + 2);
    ASSERT_EQ(grown.compensated(), expected.compensated.row(r).transpose()) << "row " << r;
  }

  // Without t the delay cannot be applied; a wrench ahead of the joints live
  // would need lines not read yet.
  std::string no_t = header.substr(2);
  EXPECT_THROW(Compensator(delayed, no_t + "\n", "stdin"), InputError);
  EXPECT_THROW(Compensator(delayed.with_delay(-0.002), header + "\n", "stdin"), InputError);
}

}  // namespace
}  // namespace massid

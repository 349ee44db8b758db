// Clock alignment (delay.hpp): a 1 kHz motion log whose wrench arrives late
// (the wrench logged at t was the mechanism's at t - delay, simulated from the
// trajectory evaluated there) gives its delay back within 0.2 ms, and the fit
// with it applied matches the URDF's base parameters as a log without lag
// does; a known delay applied gives the same; a lag beyond the scan is named.
#include <gtest/gtest.h>

#include <cmath>

#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/delay.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kLevel;

// The trajectory at 1 kHz with the wrench of the state `lag` earlier.
Samples lagged_log(const Model& model, double lag, std::uint64_t seed, double duration = 4.0) {
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
  so.noise_force = 0.1;
  so.noise_moment = 0.01;
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

}  // namespace
}  // namespace massid

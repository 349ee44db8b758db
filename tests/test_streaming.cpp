// Streaming identification (streaming.hpp) against the independent dense solve
// (identify() on the stacked regressor): every reported figure agrees to
// 1e-10 relative; block and thread splits do not change the result; the CSV
// reader accepts and rejects exactly what read_csv + read_samples do, with the
// same messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "../src/csv_stream.hpp"  // private: the fast number scanner
#include "massid/base_parameters.hpp"
#include "massid/csv.hpp"
#include "massid/errors.hpp"
#include "massid/estimation.hpp"
#include "massid/regressor.hpp"
#include "massid/simulate.hpp"
#include "massid/streaming.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

namespace fs = std::filesystem;

const Wrench kOffset = (Wrench() << 0.5, -0.3, 1.0, 0.05, -0.02, 0.03).finished();

// Plans that determine the offsets too (three or more gravity directions).
std::string offset_plan(const test::Example& ex) {
  if (ex.name == "puma260") return MASSID_SOURCE_DIR "/examples/puma260/holdout.csv";
  return ex.plan;
}

// The plan's rows repeated `repeat` times, with simulated noisy wrenches.
Samples noisy_data(const Model& model, const std::string& plan_path, bool offset, int repeat,
                   std::uint64_t seed) {
  const Samples plan = test::load_plan(model, plan_path);
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.seed = seed;
  so.repeat = repeat;
  if (offset) so.offset = kOffset;
  Samples s;
  s.source = plan.source;
  const int n = plan.size() * repeat;
  s.q.resize(n, plan.q.cols());
  s.gravity.resize(n, 3);
  for (int i = 0; i < plan.size(); ++i)
    for (int r = 0; r < repeat; ++r) {
      s.q.row(i * repeat + r) = plan.q.row(i);
      s.gravity.row(i * repeat + r) = plan.gravity.row(i);
      s.line.push_back(i + 1);
    }
  s.wrench = simulate_wrenches(model, plan, so);
  return s;
}

// Random joint positions and tilts up to 30 degrees, noisy wrenches.
Samples random_data(const Model& model, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Samples s;
  s.source = "random";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j)
      s.q(i, j) = model.joints[j].generic_position(u(rng));
    const double tilt = 0.5 * u(rng), az = 6.283 * u(rng);
    s.gravity.row(i) =
        -kStandardGravity * Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                            std::sin(tilt) * std::sin(az), std::cos(tilt));
  }
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.seed = seed;
  s.wrench = simulate_wrenches(model, s, so);
  return s;
}

// |a - b| <= rel * max(|a_i|, |b_i|), with a floor of rel * 1e-6 * max|a|
// for entries that are nearly zero (covariances between unrelated unknowns).
void expect_close(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double rel,
                  const std::string& what) {
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  const double floor = 1e-6 * a.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double x = a.data()[i], y = b.data()[i];
    EXPECT_LE(std::abs(x - y), rel * std::max({std::abs(x), std::abs(y), floor}))
        << what << "[" << i << "]: " << x << " vs " << y;
  }
}

void expect_same_summary(const IdentifySummary& d, const IdentifySummary& s, double rel,
                         bool residual_max = true) {
  expect_close(d.value, s.value, rel, "value");
  expect_close(d.stddev, s.stddev, rel, "stddev");
  // Covariances relative to sqrt(C_ii C_jj): entries between nearly
  // uncorrelated unknowns are round-off of that size.
  ASSERT_EQ(d.covariance.rows(), s.covariance.rows());
  for (Eigen::Index i = 0; i < d.covariance.rows(); ++i)
    for (Eigen::Index j = 0; j < d.covariance.cols(); ++j)
      EXPECT_LE(std::abs(d.covariance(i, j) - s.covariance(i, j)),
                rel * std::sqrt(d.covariance(i, i) * d.covariance(j, j)))
          << "covariance(" << i << "," << j << ")";
  expect_close(Eigen::VectorXd::Constant(1, d.condition_number),
               Eigen::VectorXd::Constant(1, s.condition_number), rel, "condition number");
  expect_close(d.residual_rms, s.residual_rms, rel, "residual_rms");
  if (residual_max) expect_close(d.residual_max, s.residual_max, rel, "residual_max");
  expect_close(d.sigma, s.sigma, rel, "sigma");
  expect_close(Eigen::VectorXd::Constant(1, d.chi2_per_dof),
               Eigen::VectorXd::Constant(1, s.chi2_per_dof), rel, "chi2_per_dof");
  EXPECT_EQ(d.samples, s.samples);
  EXPECT_EQ(d.sigma_estimated, s.sigma_estimated);
  EXPECT_EQ(d.gravity_from_force, s.gravity_from_force);
}

void expect_identical(const IdentifySummary& a, const IdentifySummary& b) {
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.stddev, b.stddev);
  EXPECT_EQ(a.covariance, b.covariance);
  EXPECT_EQ(a.condition_number, b.condition_number);
  EXPECT_EQ(a.residual_rms, b.residual_rms);
  EXPECT_EQ(a.residual_max, b.residual_max);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_EQ(a.chi2_per_dof, b.chi2_per_dof);
  EXPECT_EQ(a.samples, b.samples);
}

// Writes samples as a data CSV (shortest round-trip numbers: the file holds
// exactly the doubles of `s`), with an unused column and a comment.
void write_data(const Model& model, const Samples& s, const std::string& path,
                bool with_gravity = true) {
  std::ofstream out(path);
  out << "# generated by test_streaming\n";
  for (const auto& j : model.joints) out << j.name << ",";
  out << "note,fx,fy,fz,mx,my,mz";
  if (with_gravity) out << ",gx,gy,gz";
  out << "\n";
  for (int i = 0; i < s.size(); ++i) {
    for (int j = 0; j < s.q.cols(); ++j) out << format_number(s.q(i, j)) << ",";
    out << "x";
    for (int k = 0; k < 6; ++k) out << "," << format_number(s.wrench(i, k));
    if (with_gravity)
      for (int k = 0; k < 3; ++k) out << "," << format_number(s.gravity(i, k));
    out << "\n";
  }
}

class StreamingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() /
        ("massid_streaming_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string file(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  fs::path dir_;
};

// ---------------------------------------------------------------- against dense

TEST_F(StreamingTest, AgreesWithDenseOnEveryExample) {
  for (const auto& ex : test::examples())
    for (const bool offset : {false, true})
      for (const bool given_sigma : {false, true}) {
        SCOPED_TRACE(ex.name + (offset ? " offset" : "") + (given_sigma ? " sigma" : ""));
        const Model model = load_urdf(ex.urdf);
        BaseParameterOptions bo;
        bo.offset = offset;
        const BaseParameters base = find_base_parameters(model, bo);
        const Samples s = noisy_data(model, offset ? offset_plan(ex) : ex.plan, offset, 3, 11);
        IdentifyOptions opts;
        if (given_sigma) {
          opts.sigma_force = 0.04;
          opts.sigma_moment = 0.006;
        }
        const IdentifySummary dense = identify(model, base, s, opts);
        StreamOptions so;
        so.block_rows = 37;  // many merges
        so.threads = 2;
        expect_same_summary(dense, identify_streaming(model, base, s, opts, so), 1e-10);

        // The accumulator fed directly, and CSV.
        IdentifyAccumulator acc(model, base);
        acc.add(s);
        acc.set_source(s.source, false);
        expect_same_summary(dense, acc.finish(opts), 1e-10, false);
        const std::string csv = path(ex.name + ".csv");
        write_data(model, s, csv);
        so.block_bytes = 4096;
        expect_same_summary(dense, identify_csv(model, base, csv, opts, so), 1e-10);
      }
}

TEST_F(StreamingTest, RandomLogOfTenThousandRowsAgreesWithDense) {
  const auto ex = test::examples()[1];  // ur_like
  const Model model = load_urdf(ex.urdf);
  for (const bool offset : {false, true}) {
    BaseParameterOptions bo;
    bo.offset = offset;
    const BaseParameters base = find_base_parameters(model, bo);
    Samples s = random_data(model, 10000, 5);
    if (offset)
      for (int i = 0; i < s.size(); ++i) s.wrench.row(i) += kOffset.transpose();
    expect_same_summary(identify(model, base, s), identify_streaming(model, base, s), 1e-10);
  }
}

// ResidualMax evaluates its samples in batches of the streaming regressor
// (vectorised across samples, all joint types): the largest residual per axis
// is the dense one, whatever the batch boundaries, the order of the samples,
// or when max() is asked.
TEST_F(StreamingTest, ResidualMaxAgreesWithDenseInAnyBatching) {
  for (const auto& ex : test::examples()) {
    SCOPED_TRACE(ex.name);
    const Model model = load_urdf(ex.urdf);
    const BaseParameters base = find_base_parameters(model);
    const Samples s = random_data(model, 1000, 21);  // 7 full batches and a partial one
    const IdentifySummary dense = identify(model, base, s);
    const int nj = model.num_joints();
    auto add_row = [&](ResidualMax& r, int i) {
      const Eigen::VectorXd q = s.q.row(i).transpose();
      const Eigen::Vector3d g = s.gravity.row(i).transpose();
      const Eigen::Matrix<double, 6, 1> w = s.wrench.row(i).transpose();
      ASSERT_EQ(q.size(), nj);
      r.add(q.data(), g.data(), w.data());
    };
    ResidualMax forward(model, base, dense.value);
    for (int i = 0; i < 300; ++i) add_row(forward, i);
    const Eigen::Matrix<double, 6, 1> part = forward.max();  // evaluates a partial batch
    for (int i = 300; i < s.size(); ++i) add_row(forward, i);
    const Eigen::Matrix<double, 6, 1> all = forward.max();
    EXPECT_TRUE((part.array() <= all.array()).all());
    expect_close(dense.residual_max, all, 1e-10, "residual_max");
    // Every sample gets the same operations wherever it sits in a batch: the
    // samples in reverse order, and split over two merged halves, give the
    // same bits.
    ResidualMax backward(model, base, dense.value);
    for (int i = s.size() - 1; i >= 0; --i) add_row(backward, i);
    EXPECT_EQ(all, backward.max());
    ResidualMax first(model, base, dense.value), second(model, base, dense.value);
    for (int i = 0; i < 517; ++i) add_row(first, i);
    for (int i = 517; i < s.size(); ++i) add_row(second, i);
    first.merge(second);
    EXPECT_EQ(all, first.max());
  }
}

// ---------------------------------------------------------------- determinism

TEST_F(StreamingTest, ThreadCountDoesNotChangeTheResult) {
  const auto ex = test::examples()[1];
  const Model model = load_urdf(ex.urdf);
  const BaseParameters base = find_base_parameters(model);
  const Samples s = random_data(model, 5000, 9);
  StreamOptions so;
  so.block_rows = 300;
  so.threads = 1;
  const IdentifySummary one = identify_streaming(model, base, s, {}, so);
  for (const int threads : {2, 3, 8}) {
    so.threads = threads;
    expect_identical(one, identify_streaming(model, base, s, {}, so));
  }
  // Other block sizes: other rounding only (the block size is part of the
  // definition of the bits, like the order of a sum).
  for (const int rows : {7, 128, 4999, 100000}) {
    so.block_rows = rows;
    expect_same_summary(one, identify_streaming(model, base, s, {}, so), 1e-10);
  }

  const std::string csv = path("log.csv");
  write_data(model, s, csv);
  StreamOptions cs;
  cs.block_bytes = 10000;
  cs.threads = 1;
  const IdentifySummary from_csv = identify_csv(model, base, csv, {}, cs);
  for (const int threads : {2, 4}) {
    cs.threads = threads;
    expect_identical(from_csv, identify_csv(model, base, csv, {}, cs));
  }
  for (const size_t bytes : {size_t{100}, size_t{3333}, size_t{1} << 30}) {
    cs.block_bytes = bytes;
    expect_same_summary(from_csv, identify_csv(model, base, csv, {}, cs), 1e-10);
  }
}

// ---------------------------------------------------------------- CSV

TEST_F(StreamingTest, HundredThousandRowCsvRoundTrip) {
  const auto ex = test::examples()[1];
  const Model model = load_urdf(ex.urdf);
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = random_data(model, 100000, 3);
  for (int i = 0; i < s.size(); ++i) s.wrench.row(i) += kOffset.transpose();
  const std::string csv = path("big.csv");
  write_data(model, s, csv);
  const Samples read = read_samples(model, read_csv(csv), WrenchColumns::Required);
  ASSERT_EQ(read.q, s.q);  // the file holds exactly these doubles
  const IdentifySummary dense = identify(model, base, read);
  const IdentifySummary streamed = identify_csv(model, base, csv);
  expect_same_summary(dense, streamed, 1e-10);
  EXPECT_EQ(streamed.samples, 100000);

  // The largest residual, when proven in the first pass from the candidate
  // rows (the file is larger than the pilot), is the second pass' value
  // exactly; without offsets (a better pilot estimate) it is proven here.
  EXPECT_EQ(streamed.residual_max, residual_max_csv(model, base, csv, streamed.value));
  const IdentifySummary one_pass = accumulate_csv(model, base, csv).finish();
  if (!one_pass.residual_max.hasNaN()) {
    EXPECT_EQ(one_pass.residual_max, streamed.residual_max);
  }
  const BaseParameters no_offset = find_base_parameters(model);
  const std::string plain = path("plain.csv");
  const Samples s0 = random_data(model, 100000, 4);
  write_data(model, s0, plain);
  const IdentifySummary proven = accumulate_csv(model, no_offset, plain).finish();
  ASSERT_FALSE(proven.residual_max.hasNaN());
  EXPECT_EQ(proven.residual_max, residual_max_csv(model, no_offset, plain, proven.value));
  expect_same_summary(identify(model, no_offset, s0), proven, 1e-10);
}

// The CSV fast path reads plain decimals itself (csv_fast::plain_decimal):
// either it declines, or it gives fast_float's double and end, bit for bit.
TEST(PlainDecimal, SameDoubleAsFastFloat) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> e10(-30, 30);
  std::vector<std::string> texts = {"0",
                                    "-0",
                                    "0.0",
                                    "-0.0",
                                    "1.",
                                    ".5",
                                    "-.5",
                                    "12",
                                    "007.5",
                                    "1e5",
                                    "1.5E-3",
                                    ".",
                                    "-",
                                    "",
                                    "abc",
                                    "9007199254740993",
                                    "0.1000000000000000055511151231257827",
                                    "12345678901234567890",
                                    "1234567890123456789",
                                    "0.000000000000000000000001",
                                    "4.9406564584124654e-324"};
  char buf[64];
  for (int i = 0; i < 200000; ++i) {
    const double x = u(rng) * std::pow(10.0, e10(rng));
    texts.push_back(format_number(x));
    std::snprintf(buf, sizeof buf, "%.17g", x);
    texts.emplace_back(buf);
    std::snprintf(buf, sizeof buf, "%.*f", i % 24, x);
    texts.emplace_back(buf);
  }
  int taken = 0;
  for (const std::string& t : texts) {
    const char* first = t.data();
    const char* last = first + t.size();
    double mine = 0.0;
    const char* end = detail::csv_fast::plain_decimal(first, last, mine);
    if (!end) continue;
    ++taken;
    double theirs = 0.0;
    const auto r = fast_float::from_chars(first, last, theirs);
    ASSERT_EQ(r.ec, std::errc()) << t;
    EXPECT_EQ(end, r.ptr) << t;
    EXPECT_EQ(std::signbit(mine), std::signbit(theirs)) << t;
    EXPECT_EQ(mine, theirs) << t;
  }
  EXPECT_GT(taken, 150000);  // most plain forms are read by the fast scanner
}

TEST_F(StreamingTest, CsvSyntaxAsReadCsv) {
  // BOM, CRLF, comments, blank lines, quoted cells, '+' signs, JOINT_deg
  // columns, spaces around cells: the same samples as read_samples.
  const auto ex = test::examples()[0];  // puma260
  const Model model = load_urdf(ex.urdf);
  const BaseParameters base = find_base_parameters(model);
  const Samples s = noisy_data(model, ex.plan, false, 2, 4);
  std::string text =
      "\xEF\xBB\xBF# comment\r\n\r\n  joint1_deg , "
      "\"joint2\",joint3,fx,fy,fz,mx,my,mz,gx,gy,gz,x\r\n";
  for (int i = 0; i < s.size(); ++i) {
    text += format_number(s.q(i, 0) * 180.0 / std::numbers::pi) + " ,\"" +
            format_number(s.q(i, 1)) + "\",+" + format_number(s.q(i, 2));
    for (int k = 0; k < 6; ++k) text.append(",\t").append(format_number(s.wrench(i, k)));
    for (int k = 0; k < 3; ++k) text.append(",").append(format_number(s.gravity(i, k)));
    text += i % 2 ? ",\"a,b\"\r\n" : ",y\n";
    if (i % 7 == 3) text += "# a comment line\n   \n";
  }
  const std::string f = file("syntax.csv", text);
  const Samples read = read_samples(model, read_csv(f), WrenchColumns::Required);
  StreamOptions so;
  so.block_bytes = 512;
  expect_same_summary(identify(model, base, read), identify_csv(model, base, f, {}, so), 1e-10);
}

// The message of the InputError of f, or "" when there is none.
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(StreamingTest, BadCsvInputGivesReadCsvMessages) {
  const auto ex = test::examples()[0];
  const Model model = load_urdf(ex.urdf);
  const BaseParameters base = find_base_parameters(model);
  const Samples s = noisy_data(model, ex.plan, false, 20, 4);  // 600 rows
  const std::string good = path("good.csv");
  write_data(model, s, good);
  std::vector<std::string> lines;
  {
    std::ifstream in(good);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  auto with = [&](int line, const std::string& replacement) {
    std::string text;
    for (size_t i = 0; i < lines.size(); ++i)
      text += (static_cast<int>(i) + 1 == line ? replacement : lines[i]) + "\n";
    return text;
  };
  const std::string row = lines[400];  // file line 401
  auto cells = [&](int replace, const std::string& value) {
    std::string out;
    size_t start = 0;
    for (int c = 0;; ++c) {
      const size_t comma = row.find(',', start);
      out += (c == replace ? value : row.substr(start, comma - start));
      if (comma == std::string::npos) break;
      out += ",";
      start = comma + 1;
    }
    return out;
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nan", with(401, cells(1, "nan"))},
      {"inf", with(401, cells(5, "-inf"))},
      {"text", with(401, cells(12, "zero"))},
      {"empty", with(401, cells(0, ""))},
      {"short", with(401, row.substr(0, row.rfind(',')))},
      {"long", with(401, row + ",7")},
      {"space", with(401, cells(2, "1 2"))},
      {"quote", with(401, cells(4, "\"1"))},
      {"after_quote", with(401, cells(4, "\"1\"x"))},
      {"header_only", "# c\njoint1,joint2,joint3,fx,fy,fz,mx,my,mz\n# none\n\n"},
      {"empty_file", ""},
      {"no_header", "# only\r\n\r\n"},
      {"no_wrench", "joint1,joint2,joint3,gx,gy,gz\n1,2,3,0,0,1\n"},
      {"some_wrench", "joint1,joint2,joint3,fx,fy,gx,gy,gz\n1,2,3,0,0,1,0,0\n"},
      {"some_gravity", "joint1,joint2,joint3,fx,fy,fz,mx,my,mz,gx\n1,2,3,0,0,1,0,0,0,0\n"},
      {"no_joint", "joint1,joint3,fx,fy,fz,mx,my,mz\n1,3,0,0,1,0,0,0\n"},
      {"twice", "joint1,joint1,joint3\n1,2,3\n"},
      {"empty_name", "joint1,,joint3\n1,2,3\n"},
      {"zero_force",
       "joint1,joint2,joint3,fx,fy,fz,mx,my,mz\n1,2,3,0,0,1,0,0,0\n1,2,3,0,0,0,0,0,0\n"},
  };
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    const std::string f = file(name + ".csv", text);
    const std::string dense = input_error(
        [&] { const Samples d = read_samples(model, read_csv(f), WrenchColumns::Required); });
    ASSERT_NE(dense, "");
    EXPECT_NE(dense.find(f + ":"), std::string::npos) << dense;
    for (const int threads : {1, 2}) {
      StreamOptions so;
      so.threads = threads;
      so.block_bytes = 1000;  // the error is far from the first block
      EXPECT_EQ(input_error([&] { identify_csv(model, base, f, {}, so); }), dense);
    }
  }
  EXPECT_EQ(input_error([&] { identify_csv(model, base, path("missing.csv")); }),
            path("missing.csv") + ": cannot open file");
}

TEST_F(StreamingTest, FirstErrorInTheFileIsReported) {
  // Two bad rows in different blocks: the earlier one is reported, whatever
  // the threads do.
  const auto ex = test::examples()[0];
  const Model model = load_urdf(ex.urdf);
  const BaseParameters base = find_base_parameters(model);
  std::string text = "joint1,joint2,joint3,fx,fy,fz,mx,my,mz,gx,gy,gz\n";
  for (int i = 0; i < 5000; ++i)
    text += i == 3000 ? "1,2,bad,0,0,1,0,0,0,0,0,-9.8\n"
                      : (i == 4000 ? "1,2\n" : "1,2,3,0,0,1,0,0,0,0,0,-9.8\n");
  const std::string f = file("two_errors.csv", text);
  for (const int threads : {1, 2, 4}) {
    StreamOptions so;
    so.threads = threads;
    so.block_bytes = 2000;
    EXPECT_EQ(input_error([&] { identify_csv(model, base, f, {}, so); }),
              f + ":3002:5: column 'joint3': 'bad' is not a number");
  }
}

TEST_F(StreamingTest, GravityFromForce) {
  const auto ex = test::examples()[0];
  const Model model = load_urdf(ex.urdf);
  const BaseParameters base = find_base_parameters(model);
  const Samples s = noisy_data(model, ex.plan, false, 5, 8);
  const std::string f = path("nograv.csv");
  write_data(model, s, f, false);
  const Samples read = read_samples(model, read_csv(f), WrenchColumns::Required);
  ASSERT_TRUE(read.gravity_from_force);
  const IdentifySummary dense = identify(model, base, read);
  StreamOptions so;
  so.block_bytes = 700;
  const IdentifySummary streamed = identify_csv(model, base, f, {}, so);
  EXPECT_TRUE(streamed.gravity_from_force);
  expect_same_summary(dense, streamed, 1e-10);

  // With offsets: the same IdentifiabilityError.
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters with_offset = find_base_parameters(model, bo);
  std::string d, st;
  try {
    identify(model, with_offset, read);
  } catch (const IdentifiabilityError& e) {
    d = e.what();
  }
  try {
    identify_csv(model, with_offset, f);
  } catch (const IdentifiabilityError& e) {
    st = e.what();
  }
  EXPECT_NE(d, "");
  EXPECT_EQ(d, st);
}

// ---------------------------------------------------------------- identifiability

TEST_F(StreamingTest, UndeterminedDataGivesTheDenseMessage) {
  const auto ex = test::examples()[0];
  const Model model = load_urdf(ex.urdf);
  // Short (all samples kept) and long (more than the kept subsample) data.
  for (const int repeat : {1, 40}) {
    SCOPED_TRACE(repeat);
    Samples s = noisy_data(model, ex.plan, false, repeat, 2);
    for (int i = 0; i < s.size(); ++i) s.q(i, 2) = 0.5;  // joint3 held
    SimulateOptions so;
    so.repeat = 1;
    so.noise_force = 0.05;
    so.noise_moment = 0.005;
    s.wrench = simulate_wrenches(model, s, so);
    for (const bool offset : {false, true}) {
      BaseParameterOptions bo;
      bo.offset = offset;
      const BaseParameters base = find_base_parameters(model, bo);
      std::string d, st;
      try {
        identify(model, base, s);
      } catch (const IdentifiabilityError& e) {
        d = e.what();
      }
      try {
        identify_streaming(model, base, s);
      } catch (const IdentifiabilityError& e) {
        st = e.what();
      }
      EXPECT_NE(d, "");
      EXPECT_EQ(d, st);
    }
  }
  // Too few equations.
  const BaseParameters base = find_base_parameters(model);
  Samples one = noisy_data(model, ex.plan, false, 1, 3);
  one.q.conservativeResize(1, Eigen::NoChange);
  one.gravity.conservativeResize(1, Eigen::NoChange);
  one.wrench.conservativeResize(1, Eigen::NoChange);
  EXPECT_THROW(identify_streaming(model, base, one), IdentifiabilityError);
}

}  // namespace
}  // namespace massid

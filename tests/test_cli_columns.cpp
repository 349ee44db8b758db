// Columns named otherwise, end to end: `--columns ROLE=NAME,...` and the
// recorders' spellings of the wrench on identify, predict, simulate, design
// --evaluate and compensate; the notes that say what was read as what; the
// errors for a bad binding and a missing wrench.
#include "cli_support.hpp"
#include "column_spellings.hpp"

namespace massid_cli_test {
namespace {

const std::vector<std::vector<std::string>>& kCliSpellings = massid_test::kWrenchSpellings;
const char* const kCliWrench[6] = {"fx", "fy", "fz", "mx", "my", "mz"};

class CliColumns : public Cli {
 protected:
  // Noisy PUMA data with an offset (the held-out plan: gravity in many directions).
  std::string data() {
    const Result r = run({"simulate", kPumaUrdf, example("puma260/holdout.csv"), "-o",
                          path("data.csv"), "--noise-force", "0.05", "--noise-moment", "0.005",
                          "--sensor-offset", "0.5,-0.3,1,0.05,-0.02,0.03", "--seed", "11"});
    EXPECT_EQ(r.code, 0) << r;
    return path("data.csv");
  }
  // A copy of `in` with the wrench columns renamed to `names` (fx..mz order).
  std::string renamed(const std::string& in, const std::string& name,
                      const std::vector<std::string>& names) {
    Table t = read_table(in);
    for (int k = 0; k < 6; ++k) t.header[t.col(kCliWrench[k])] = names[k];
    return file(name, to_csv(t));
  }
  // identify --offset; the params file's text.
  std::string identify(const std::string& data, const std::vector<std::string>& extra,
                       Result* out = nullptr) {
    std::vector<std::string> args{"identify", kPumaUrdf, data, "-o", path("p.json"), "--offset"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    if (out) *out = r;
    return read_file(path("p.json"));
  }
};

// The params file's figures (values, std, residuals, offsets): everything but
// nothing that names the input.
json figures(const std::string& params) {
  json j = json::parse(params);
  json out;
  for (const char* k : {"base_parameters", "sensor_offset", "residual_rms", "condition_number"})
    out[k] = j[k];
  return out;
}

TEST_F(CliColumns, EveryCommonSpellingAndABindingIdentifyAsTheCanonicalNames) {
  const std::string d = data();
  Result canonical;
  const json ref = figures(identify(d, {}, &canonical));
  EXPECT_EQ(canonical.err.find("note:"), std::string::npos) << canonical;
  // The offsets were found (a real fit, not zeros on both sides).
  EXPECT_NEAR(ref["sensor_offset"]["force"][0].get<double>(), 0.5, 0.05);
  for (size_t s = 0; s < kCliSpellings.size(); ++s) {
    Result r;
    const json got =
        figures(identify(renamed(d, "s" + std::to_string(s) + ".csv", kCliSpellings[s]), {}, &r));
    EXPECT_EQ(got, ref) << kCliSpellings[s][0];  // bit for bit: the JSON's shortest round trip
    EXPECT_NE(r.err.find("massid: note: "), std::string::npos) << r;
    EXPECT_NE(r.err.find(kCliSpellings[s][5] + " as mz"), std::string::npos) << r;
  }
  const std::vector<std::string> odd = {"c1", "c2", "c3", "c4", "c5", "c6"};
  const std::string o = renamed(d, "odd.csv", odd);
  Result r;
  EXPECT_EQ(figures(identify(
                o, {"--columns", "fx=c1,fy=c2,fz=c3", "--columns", "mx=c4,my=c5,mz=c6"}, &r)),
            ref);
  EXPECT_NE(r.err.find("massid: note: " + o + ":1: read c1 as fx, c2 as fy"), std::string::npos)
      << r;
}

TEST_F(CliColumns, PredictWritesCompColumnsForRosNames) {
  const std::string d = data();
  identify(d, {});
  const std::string ros = renamed(d, "ros.csv", kCliSpellings[4]);
  const Result a = run({"predict", kPumaUrdf, path("p.json"), d, "-o", path("a.csv")});
  const Result b = run({"predict", kPumaUrdf, path("p.json"), ros, "-o", path("b.csv")});
  ASSERT_EQ(a.code, 0) << a;
  ASSERT_EQ(b.code, 0) << b;
  const Table ta = read_table(path("a.csv")), tb = read_table(path("b.csv"));
  ASSERT_EQ(ta.rows.size(), tb.rows.size());
  for (const char* w : kCliWrench) {
    const std::string comp = std::string(w) + "_comp";
    ASSERT_GE(tb.col(comp), 0) << comp << " missing\n" << b;
    for (size_t i = 0; i < ta.rows.size(); ++i) EXPECT_EQ(ta.num(i, comp), tb.num(i, comp));
  }
  EXPECT_NE(b.err.find("/ft_sensor/wrench/force/x as fx"), std::string::npos) << b;
  // Names nobody recognises: predicted, no _comp, and the note says why.
  const std::string odd = renamed(d, "odd.csv", {"A", "B", "C", "D", "E", "F"});
  const Result c = run({"predict", kPumaUrdf, path("p.json"), odd, "-o", path("c.csv")});
  ASSERT_EQ(c.code, 0) << c;
  EXPECT_EQ(read_table(path("c.csv")).col("fx_comp"), -1);
  EXPECT_NE(c.err.find("no measured wrench"), std::string::npos) << c;
  EXPECT_NE(c.err.find("ignored: A, B, C, D, E, F"), std::string::npos) << c;
  // ... and with --columns they are read.
  const Result e = run({"predict", kPumaUrdf, path("p.json"), odd, "-o", path("e.csv"), "--columns",
                        "fx=A,fy=B,fz=C,mx=D,my=E,mz=F"});
  ASSERT_EQ(e.code, 0) << e;
  const Table te = read_table(path("e.csv"));
  for (size_t i = 0; i < ta.rows.size(); ++i) EXPECT_EQ(ta.num(i, "mz_comp"), te.num(i, "mz_comp"));
}

TEST_F(CliColumns, BadBindingsAreClearErrors) {
  const std::string d = data();
  identify(d, {});
  const auto bad = [&](const std::string& columns, const std::vector<std::string>& pieces) {
    expect_input_error(run({"identify", kPumaUrdf, d, "-o", path("q.json"), "--columns", columns}),
                       pieces);
    expect_input_error(run({"predict", kPumaUrdf, path("p.json"), d, "--columns", columns}),
                       pieces);
  };
  bad("torque_x=mx", {d + ":1: 'torque_x=mx' binds an unknown role 'torque_x'", "joint1",
                      "(--columns ROLE=NAME)"});
  bad("mx=tx", {"no column 'tx' to read as 'mx': the header has joint1,"});
  bad("mx=fx,mx=fy", {"role 'mx' is bound twice"});
  bad("mx=fx,my=fx", {"column 'fx' is bound to two roles"});
  bad("mx", {"--columns: 'mx' should read ROLE=NAME"});
  // simulate and design --evaluate check the binding too.
  expect_input_error(
      run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("s.csv"), "--columns", "gx=nothing"}),
      {"no column 'nothing' to read as 'gx'"});
  expect_input_error(run({"design", kPumaUrdf, "--evaluate", kPumaPlan, "--columns", "bogus=gx"}),
                     {"unknown role 'bogus'"});
}

TEST_F(CliColumns, AMissingWrenchListsTheHeaderAndProposesTheBinding) {
  const std::string d = renamed(data(), "odd.csv", {"Fx", "Fy", "Fz", "a", "b", "c"});
  expect_input_error(run({"identify", kPumaUrdf, d, "-o", path("p.json")}),
                     {d + ":1: no measured wrench", "the header has joint1,joint2,joint3,gx,",
                      "(--columns fx=Fx,fy=Fy,fz=Fz,mx=NAME,my=NAME,mz=NAME)"});
  // Two spellings of one role: refused, naming both.
  Table t = read_table(renamed(data(), "two.csv", kCliSpellings[1]));
  t.header.push_back("force_x");
  for (auto& row : t.rows) row.push_back(row[t.col("Fx")]);
  const std::string two = file("two.csv", to_csv(t));
  expect_input_error(run({"identify", kPumaUrdf, two, "-o", path("p.json")}),
                     {"columns 'Fx' and 'force_x' could both be fx", "(--columns fx=Fx)"});
}

TEST_F(CliColumns, AStaticFitIgnoresAnImusAccelerationsAndSaysWhy) {
  const std::string d = data();
  const json ref = figures(identify(d, {}));
  Table t = read_table(d);
  for (const char* a : {"ax", "ay", "az"}) t.header.push_back(a);
  for (auto& row : t.rows)
    for (const char* v : {"0.02", "-0.01", "0.998"}) row.push_back(v);
  const std::string imu = file("imu.csv", to_csv(t));
  Result r;
  EXPECT_EQ(figures(identify(imu, {}, &r)), ref);
  EXPECT_NE(r.err.find("massid: note: " + imu +
                       ":1: ignored: ax, ay, az (the sensor frame's motion in part, without "
                       "wx,wy,wz,dwx,dwy,dwz: a static fit needs none"),
            std::string::npos)
      << r;
  // In motion the same columns are an error that says how they would be read.
  expect_input_error(
      run({"identify", kPumaUrdf, imu, "-o", path("p.json"), "--dynamic"}),
      {imu + ":1: column(s) wx,wy,wz,dwx,dwy,dwz missing", "acceleration without gravity, m/s^2"});
}

TEST_F(CliColumns, CompensateReadsTheSpelledHeader) {
  const std::string d = data();
  identify(d, {});
  const Result a = run({"compensate", kPumaUrdf, path("p.json")}, d);
  const Result b =
      run({"compensate", kPumaUrdf, path("p.json")}, renamed(d, "ati.csv", kCliSpellings[1]));
  ASSERT_EQ(a.code, 0) << a;
  ASSERT_EQ(b.code, 0) << b;
  EXPECT_NE(b.err.find("massid: note: stdin:1: read Fx as fx"), std::string::npos) << b;
  // The same compensated numbers, line for line (the input text differs in the header only).
  const auto body = [](const std::string& s) { return s.substr(s.find('\n')); };
  EXPECT_EQ(body(a.out), body(b.out));
  const Result c = run({"compensate", kPumaUrdf, path("p.json"), "--columns", "fx=Fx"},
                       renamed(d, "ati2.csv", {"Fx", "fy", "fz", "mx", "my", "mz"}));
  ASSERT_EQ(c.code, 0) << c;
  EXPECT_EQ(body(a.out), body(c.out));
}

}  // namespace
}  // namespace massid_cli_test

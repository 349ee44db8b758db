// identify --physical and predict --physical, as a user runs them: the table
// printed, the params file's "physical" section (every link's ten parameters
// checked for consistency here, with Eigen, not by massid), and predict
// --physical against predict of a params file whose values are K pi_phys
// computed here from the file's own terms.
#include <Eigen/Eigenvalues>

#include "cli_support.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace massid_cli_test {
namespace {

const char* kKinds[10] = {"m", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"};

// Every link of the section: exactly ten numbers, m > 0, J >= 0.
void expect_consistent_links(const json& links, size_t count) {
  ASSERT_TRUE(links.is_object());
  EXPECT_EQ(links.size(), count);
  for (const auto& [name, p] : links.items()) {
    SCOPED_TRACE(name);
    EXPECT_EQ(p.size(), 10u);
    for (const char* k : kKinds) ASSERT_TRUE(p.contains(k)) << k;
    const double m = p["m"];
    if (m == 0.0) {  // a massless frame (massless_links): all ten zero
      for (const char* k : kKinds) EXPECT_EQ(p[k].get<double>(), 0.0) << k;
      continue;
    }
    EXPECT_GT(m, 0.0);
    Eigen::Matrix3d I;
    I << p["ixx"], p["ixy"], p["ixz"], p["ixy"], p["iyy"], p["iyz"], p["ixz"], p["iyz"], p["izz"];
    Eigen::Matrix4d J;
    J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
    J.block<3, 1>(0, 3) << p["mx"], p["my"], p["mz"];
    J.block<1, 3>(3, 0) = J.block<3, 1>(0, 3).transpose();
    J(3, 3) = m;
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J).eigenvalues()[0],
              -1e-12 * J.trace());
  }
}

// The params file with every base parameter's value replaced by its terms
// evaluated on the physical section (K pi_phys), and the section dropped.
json with_physical_values(json p) {
  const json& links = p["physical"]["links"];
  for (auto& e : p["base_parameters"]) {
    double v = 0.0;
    for (const auto& t : e["terms"])
      v += t["coef"].get<double>() *
           links.at(t["link"].get<std::string>()).at(t["param"].get<std::string>()).get<double>();
    e["value"] = v;
  }
  p.erase("physical");
  return p;
}

class CliPhysical : public Cli {
 protected:
  // The PUMA's plan simulated with noise (data.csv), identified --physical (params.json).
  Result identify_puma() {
    const Result sim = run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("data.csv"),
                            "--noise-force", "0.05", "--noise-moment", "0.005", "--seed", "1"});
    EXPECT_EQ(sim.code, 0) << sim;
    const Result r =
        run({"identify", kPumaUrdf, path("data.csv"), "--physical", "-o", path("params.json")});
    EXPECT_EQ(r.code, 0) << r;
    return r;
  }
  // predict --physical equals predict of the file carrying K pi_phys.
  void expect_physical_prediction(const std::vector<std::string>& predict_args,
                                  const std::string& params, const std::string& data) {
    auto predict = [&](const std::string& file, const std::string& out, bool physical) {
      std::vector<std::string> a = predict_args;
      a.insert(a.end(), {file, data, "-o", path(out)});
      if (physical) a.push_back("--physical");
      const Result res = run(a);
      EXPECT_EQ(res.code, 0) << res;
      return read_table(path(out));
    };
    write_file(path("direct.json"), with_physical_values(json::parse(read_file(params))).dump());
    const Table a = predict(params, "phys.csv", true),
                b = predict(path("direct.json"), "direct.csv", false);
    ASSERT_EQ(a.rows.size(), b.rows.size());
    ASSERT_GT(a.rows.size(), 0u);
    for (const char* c : {"fx_pred", "fy_pred", "fz_pred", "mx_pred", "my_pred", "mz_pred"})
      for (size_t r = 0; r < a.rows.size(); r += 7)
        EXPECT_NEAR(a.num(r, c), b.num(r, c), 1e-9 * (1 + std::abs(b.num(r, c)))) << c << r;
  }
};

TEST_F(CliPhysical, DynamicIdentifyPrintsTheTableAndPredictUsesIt) {
  Result r = run({"design", kUrUrdf, "--dynamic", "-o", path("traj.csv"), "--duration", "10",
                  "--rate", "200", "--seed", "1"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"simulate", kUrUrdf, path("traj.csv"), "-o", path("log.csv"), "--dynamic",
           "--noise-force", "0.1", "--noise-moment", "0.01", "--sensor-offset", "1,2,3,0.1,0.2,0.3",
           "--seed", "2"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kUrUrdf, path("log.csv"), "--dynamic", "--offset", "--physical", "-o",
           path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("physically consistent parameters (--physical"), std::string::npos) << r;
  EXPECT_NE(r.out.find("forearm_link"), std::string::npos) << r;
  EXPECT_NE(r.out.find("worst base-parameter mismatch"), std::string::npos) << r;
  EXPECT_NE(r.out.find("within std"), std::string::npos) << r;
  EXPECT_NE(r.out.find("no mass in the URDF, fixed to a neighbour: massless"), std::string::npos)
      << r;  // the sensor link
  const json p = json::parse(read_file(path("params.json")));
  ASSERT_TRUE(p.contains("physical")) << p.dump(1);
  expect_consistent_links(p["physical"]["links"], 10);
  EXPECT_TRUE(p["physical"]["consistent"].get<bool>());
  EXPECT_LE(std::abs(p["physical"]["worst_mismatch"]["std"].get<double>()), 2.0);
  expect_physical_prediction({"predict", kUrUrdf}, path("params.json"), path("log.csv"));
  // No link turned into a needle: where the data see a link's products of
  // inertia only to within its own inertia (the shoulder on a 10 s log), the
  // prior keeps its principal moments near the URDF's (a weak prior on the
  // arm's global scale let the smallest fall to 1e-8 kg m^2).
  const massid::Model urdf = massid::load_urdf(kUrUrdf);
  for (const massid::Link& link : urdf.links) {
    if (!(link.mass > 0)) continue;
    const json& q = p["physical"]["links"][link.name];
    const double m = q["m"];
    const Eigen::Vector3d c(q["mx"].get<double>() / m, q["my"].get<double>() / m,
                            q["mz"].get<double>() / m);
    Eigen::Matrix3d I;
    I << q["ixx"], q["ixy"], q["ixz"], q["ixy"], q["iyy"], q["iyz"], q["ixz"], q["iyz"], q["izz"];
    I -= m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues()[0];
    const double urdf_smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(link.inertia).eigenvalues()[0];
    EXPECT_GT(smallest, 0.2 * urdf_smallest) << link.name;
  }
  // Without --physical the file has no such section, and predict --physical says so.
  r = run(
      {"identify", kUrUrdf, path("log.csv"), "--dynamic", "--offset", "-o", path("plain.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_FALSE(json::parse(read_file(path("plain.json"))).contains("physical"));
  r = run({"predict", kUrUrdf, path("plain.json"), path("log.csv"), "--physical"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("no \"physical\" section"), std::string::npos) << r;
}

TEST_F(CliPhysical, StaticIdentifyGivesMassesAndPredictUsesThem) {
  const Result r = identify_puma();
  EXPECT_NE(r.out.find("inertia about each centre of mass from the URDF"), std::string::npos) << r;
  const json p = json::parse(read_file(path("params.json")));
  expect_consistent_links(p["physical"]["links"], 5);
  EXPECT_EQ(p["physical"]["inertia_from"], "urdf (about the centre of mass)");
  expect_physical_prediction({"predict", kPumaUrdf}, path("params.json"), path("data.csv"));
}

TEST_F(CliPhysical, ABrokenPhysicalSectionIsAnInputError) {
  Result r = identify_puma();
  json p = json::parse(read_file(path("params.json")));
  p["physical"]["links"]["link2"].erase("izz");
  write_file(path("broken.json"), p.dump());
  r = run({"predict", kPumaUrdf, path("broken.json"), path("data.csv"), "--physical"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("link 'link2' needs a number \"izz\""), std::string::npos) << r;
  p = json::parse(read_file(path("params.json")));
  p["physical"]["links"].erase("link3");
  write_file(path("missing.json"), p.dump());
  r = run({"predict", kPumaUrdf, path("missing.json"), path("data.csv"), "--physical"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("no parameters for link 'link3'"), std::string::npos) << r;
}

}  // namespace
}  // namespace massid_cli_test

namespace massid_cli_test {
namespace {

// identify --urdf-out: the URDF with the physical inertials reloads (urdfdom,
// through simulate), and simulate on it gives the wrench predict --physical
// ascribes to the same rows, at rest (masses and centres of mass) and in motion
// (full inertials); everything outside the measured links' inertials is kept.
class CliUrdfOut : public Cli {
 protected:
  void expect_same_wrench(const std::string& simulated, const std::string& predicted) {
    const Table s = read_table(simulated), p = read_table(predicted);
    ASSERT_EQ(s.rows.size(), p.rows.size());
    ASSERT_GT(s.rows.size(), 0u);
    const char* axes[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
    for (const char* a : axes)
      for (size_t r = 0; r < s.rows.size(); ++r)
        ASSERT_NEAR(s.num(r, a), p.num(r, std::string(a) + "_pred"),
                    1e-8 * (1 + std::abs(s.num(r, a))))
            << a << " row " << r;
  }
};

TEST_F(CliUrdfOut, StaticIdentifiedUrdfReproducesThePhysicalPrediction) {
  ASSERT_EQ(run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("data.csv"), "--noise-force", "0.05",
                 "--noise-moment", "0.005", "--seed", "1"})
                .code,
            0);
  const Result r = run({"identify", kPumaUrdf, path("data.csv"), "-o", path("params.json"),
                        "--urdf-out", path("puma_identified.urdf")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("physically consistent parameters"), std::string::npos) << r;  // implied
  EXPECT_NE(r.out.find("masses and centres of mass), every other byte as it was"),
            std::string::npos)
      << r;
  const std::string text = read_file(path("puma_identified.urdf"));
  EXPECT_NE(text.find("identified by massid from"), std::string::npos);
  ASSERT_EQ(run({"simulate", path("puma_identified.urdf"), kPumaPlan, "-o", path("sim.csv")}).code,
            0);
  ASSERT_EQ(run({"predict", kPumaUrdf, path("params.json"), path("data.csv"), "-o",
                 path("pred.csv"), "--physical"})
                .code,
            0);
  expect_same_wrench(path("sim.csv"), path("pred.csv"));
}

TEST_F(CliUrdfOut, DynamicIdentifiedUrdfReproducesThePhysicalPrediction) {
  ASSERT_EQ(run({"design", kUrUrdf, "--dynamic", "-o", path("traj.csv"), "--duration", "6",
                 "--period", "6", "--rate", "100", "--harmonics", "3", "--evaluations", "300"})
                .code,
            0);
  ASSERT_EQ(run({"simulate", kUrUrdf, path("traj.csv"), "-o", path("log.csv"), "--dynamic",
                 "--noise-force", "0.1", "--noise-moment", "0.01", "--seed", "2"})
                .code,
            0);
  const Result r = run({"identify", kUrUrdf, path("log.csv"), "--dynamic", "-o",
                        path("params.json"), "--urdf-out", path("ur_identified.urdf")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("masses, centres of mass, inertias), every other byte"), std::string::npos)
      << r;
  ASSERT_EQ(run({"simulate", path("ur_identified.urdf"), path("traj.csv"), "-o", path("sim.csv"),
                 "--dynamic"})
                .code,
            0);
  ASSERT_EQ(run({"predict", kUrUrdf, path("params.json"), path("log.csv"), "-o", path("pred.csv"),
                 "--physical"})
                .code,
            0);
  expect_same_wrench(path("sim.csv"), path("pred.csv"));
  // A URDF that cannot be written to: exit 2, nothing left behind.
  const Result bad = run({"identify", kUrUrdf, path("log.csv"), "--dynamic", "-o", path("p2.json"),
                          "--urdf-out", path("no/such/dir/x.urdf")});
  EXPECT_EQ(bad.code, 2) << bad;
}

// The text of <link name="NAME"> .. its end in a URDF ("" when absent).
std::string physical_link_text(const std::string& urdf, const std::string& name) {
  const size_t at = urdf.find("<link name=\"" + name + "\"");
  if (at == std::string::npos) return "";
  const size_t self = urdf.find("/>", at), open = urdf.find('>', at);
  if (self != std::string::npos && self + 1 == open) return urdf.substr(at, self + 2 - at);
  return urdf.substr(at, urdf.find("</link>", at) + 7 - at);
}

// The UR5 as published: root `world` without <inertial>, the massless frames
// ee_link, base and tool0 (mass 0). Identified at rest, the identified URDF
// leaves them as they were (no 2 g bodies, no root inertial), the physical
// section says they are massless (all ten 0), and the file still reproduces
// predict --physical.
TEST_F(CliUrdfOut, MasslessFramesStayMasslessAndTheRootGetsNoInertial) {
  const std::string ur5 = kSource + "/tests/data/robots/ur5_robot.urdf";
  ASSERT_EQ(run({"design", ur5, "-o", path("plan.csv"), "--poses", "60", "--tilt-max", "25",
                 "--seed", "1"})
                .code,
            0);
  ASSERT_EQ(run({"simulate", ur5, path("plan.csv"), "-o", path("data.csv"), "--noise-force", "0.05",
                 "--noise-moment", "0.005", "--seed", "1"})
                .code,
            0);
  const Result r = run({"identify", ur5, path("data.csv"), "-o", path("params.json"), "--urdf-out",
                        path("ur5_identified.urdf")});
  ASSERT_EQ(r.code, 0) << r;
  const std::string in = read_file(ur5), out = read_file(path("ur5_identified.urdf"));
  EXPECT_EQ(physical_link_text(out, "world"), "<link name=\"world\"/>");
  for (const char* frame : {"ee_link", "tool0", "base"}) {
    EXPECT_NE(physical_link_text(out, frame), "") << frame;
    EXPECT_EQ(physical_link_text(out, frame), physical_link_text(in, frame)) << frame;
  }
  EXPECT_NE(physical_link_text(out, "wrist_3_link").find("identified by massid"),
            std::string::npos);
  const json params = json::parse(read_file(path("params.json")));
  const json& massless = params["physical"]["massless_links"];
  for (const char* frame : {"ee_link", "tool0", "base", "world"}) {
    EXPECT_NE(std::find(massless.begin(), massless.end(), frame), massless.end()) << frame;
    for (const auto& [kind, v] : params["physical"]["links"][frame].items())
      EXPECT_EQ(v.get<double>(), 0.0) << frame << " " << kind;
  }
  EXPECT_EQ(params["physical"]["consistent"], true);
  ASSERT_EQ(
      run({"simulate", path("ur5_identified.urdf"), path("plan.csv"), "-o", path("sim.csv")}).code,
      0);
  ASSERT_EQ(run({"predict", ur5, path("params.json"), path("data.csv"), "-o", path("pred.csv"),
                 "--physical"})
                .code,
            0);
  expect_same_wrench(path("sim.csv"), path("pred.csv"));
}

// A physical fit stopped before it converged (--physical-iterations 1): a
// warning, the params file with "converged": false, no URDF and exit 4;
// --accept-unconverged writes the URDF, warns and exits 0.
TEST_F(CliUrdfOut, UnconvergedPhysicalFitWarnsAndExits4) {
  ASSERT_EQ(run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("data.csv"), "--noise-force", "0.05",
                 "--noise-moment", "0.005", "--seed", "1"})
                .code,
            0);
  Result r = run({"identify", kPumaUrdf, path("data.csv"), "-o", path("params.json"), "--urdf-out",
                  path("x.urdf"), "--physical-iterations", "1"});
  EXPECT_EQ(r.code, 4) << r;
  EXPECT_NE(r.err.find("massid: warning: the physical fit did not converge (1 iterations"),
            std::string::npos)
      << r;
  EXPECT_NE(r.err.find("is not written"), std::string::npos) << r;
  EXPECT_NE(r.err.find("--accept-unconverged"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(path("x.urdf")));
  const json params = json::parse(read_file(path("params.json")));
  EXPECT_EQ(params["physical"]["solver"]["converged"], false);
  EXPECT_EQ(params["physical"]["solver"]["iterations"], 1);
  r = run({"identify", kPumaUrdf, path("data.csv"), "-o", path("params2.json"), "--urdf-out",
           path("x.urdf"), "--physical-iterations", "1", "--accept-unconverged"});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r;
  EXPECT_TRUE(fs::exists(path("x.urdf")));
  // The default limit converges: no warning.
  r = run({"identify", kPumaUrdf, path("data.csv"), "-o", path("params3.json"), "--physical"});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err.find("did not converge"), std::string::npos) << r;
}

}  // namespace
}  // namespace massid_cli_test

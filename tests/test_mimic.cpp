// Mimic joints (URDF <mimic joint= multiplier= offset=>): the link moves with
// its master, q = multiplier q_master + offset. Checked against the same URDF
// with the <mimic> tag removed (an independent joint set to that position),
// for the standard regressor, the base regressor in motion, and the compiled
// static and motion predictors; the published Panda and Robotiq 2F-85
// descriptions load; chains, cycles and bad masters are named at once.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>
#include <regex>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/io/urdf.hpp"
#include "mimic_support.hpp"

namespace massid {
namespace {

using test::expand;
using test::gripper_urdf;

const std::string kRobotsDir = MASSID_SOURCE_DIR "/tests/data/robots/";

TEST(Mimic, LoadsWithTheMasterAndNoJointOfItsOwn) {
  const Model with = load_urdf_string(gripper_urdf(true), "", "g.urdf");
  EXPECT_EQ(with.num_joints(), 3);  // shoulder, finger_a, slide_a
  ASSERT_EQ(with.mimics.size(), 2u);
  EXPECT_EQ(with.mimics[0].master, "finger_a");
  EXPECT_EQ(with.mimics[0].multiplier, -1.5);
  EXPECT_EQ(with.mimics[0].offset, 0.2);
  const Link& fb = with.links[with.find_link("fb")];
  EXPECT_EQ(fb.joint_index, with.find_joint("finger_a"));
  EXPECT_EQ(fb.joint_scale, -1.5);
  // finger_b in [-0.4, 1.0] with q_b = -1.5 q_a + 0.2: q_a in [-0.5333, 0.4];
  // finger_a's own [-0.5, 0.6]: [-0.5, 0.4].
  const Joint& fa = with.joints[with.find_joint("finger_a")];
  EXPECT_DOUBLE_EQ(fa.lower, -0.5);
  EXPECT_DOUBLE_EQ(fa.upper, 0.4);
  EXPECT_DOUBLE_EQ(fa.urdf_upper, 0.6);
  // slide_b in [-0.1, 0.1] = 0.5 q + 0.01: q in [-0.22, 0.18]; slide_a's own [-0.05, 0.05].
  const Joint& sa = with.joints[with.find_joint("slide_a")];
  EXPECT_DOUBLE_EQ(sa.lower, -0.05);
  EXPECT_DOUBLE_EQ(sa.upper, 0.05);
}

TEST(Mimic, RegressorsAndPredictorsEqualTheModelWithTheJointSet) {
  const Model with = load_urdf_string(gripper_urdf(true), "", "g.urdf");
  const Model without = load_urdf_string(gripper_urdf(false), "", "g0.urdf");
  ASSERT_EQ(without.num_joints(), 5);
  ASSERT_EQ(with.num_links(), without.num_links());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random = [&](int n, double scale) {
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = scale * u(rng);
    return v;
  };
  // The same standard parameters (the links are the same, in the same order).
  const Eigen::VectorXd pi_with = ParameterLayout::full().nominal(with);
  const Eigen::VectorXd pi_without = ParameterLayout::full().nominal(without);
  ASSERT_TRUE(pi_with.isApprox(pi_without, 0.0));

  // Static: predictor compiled from the base parameters against Y(q) pi of
  // the model without mimic joints.
  const BaseParameters base_with = find_base_parameters(with);
  const Predictor pred =
      compile_predictor(with, base_with, base_with.K * nominal_standard_parameters(with));
  PredictorData pdata(pred);
  KinematicsData kw(with), k0(without);
  Eigen::MatrixXd Yw(6, num_standard_parameters(with)), Y0(6, num_standard_parameters(without));
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = random(with.num_joints(), 0.6);
    Eigen::Vector3d g = random(3, 1.0);
    g *= 9.81 / g.norm();
    forward_kinematics(with, kw, q);
    forward_kinematics(without, k0, expand(with, without, q, false));
    standard_regressor(with, kw, g, Yw);
    standard_regressor(without, k0, g, Y0);
    ASSERT_TRUE(Yw.isApprox(Y0, 1e-13)) << trial;
    const Wrench w0 = Y0 * nominal_standard_parameters(without);
    const Wrench wp = predict(pred, pdata, q, g);
    EXPECT_LT((wp - w0).norm(), 1e-12 * (1.0 + w0.norm())) << trial;
  }

  // Motion: the motion regressor, and the motion predictor, in motion with
  // the master's velocity and acceleration scaled by the multiplier.
  BaseParameterOptions bo;
  bo.layout = ParameterLayout::full();
  const BaseParameters mbase = find_base_parameters(with, bo);
  const MotionPredictor mp = compile_motion_predictor(with, mbase, mbase.K * pi_with);
  MotionPredictorData mdata(mp);
  Eigen::MatrixXd Mw(6, 10 * with.num_links()), M0(6, 10 * without.num_links());
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = random(with.num_joints(), 0.6);
    const Eigen::VectorXd qd = random(with.num_joints(), 2.0);
    const Eigen::VectorXd qdd = random(with.num_joints(), 5.0);
    const Eigen::Vector3d g(0.5, -1.0, -9.7);
    forward_kinematics(with, kw, q, qd, qdd, g);
    forward_kinematics(without, k0, expand(with, without, q, false),
                       expand(with, without, qd, true), expand(with, without, qdd, true), g);
    motion_regressor(with, kw, Mw);
    motion_regressor(without, k0, M0);
    ASSERT_TRUE(Mw.isApprox(M0, 1e-12)) << trial;
    const Wrench w0 = M0 * pi_without;
    const Wrench wp = predict_motion(mp, mdata, q.data(), qd.data(), qdd.data(), g);
    EXPECT_LT((wp - w0).norm(), 1e-10 * (1.0 + w0.norm())) << trial;
  }
}

TEST(Mimic, HoldingAMimicJointHoldsItsMaster) {
  const Model with = load_urdf_string(gripper_urdf(true), "", "g.urdf");
  // finger_b at 0.5 <=> finger_a at (0.5 - 0.2) / -1.5 = -0.2
  const Model held = hold_joints(with, {{"finger_b", 0.5}});
  EXPECT_EQ(held.find_joint("finger_a"), -1);
  ASSERT_EQ(held.held.size(), 1u);
  EXPECT_EQ(held.held[0].first, "finger_a");
  EXPECT_DOUBLE_EQ(held.held[0].second, -0.2);
  EXPECT_EQ(held.mimics.size(), 1u);  // slide_b still follows slide_a
  // The held model's wrench is the full model's at finger_a = -0.2.
  Eigen::VectorXd q_full(3), q_held(2);
  q_full << 0.4, -0.2, 0.03;
  q_held << 0.4, 0.03;
  KinematicsData kf(with), kh(held);
  forward_kinematics(with, kf, q_full);
  forward_kinematics(held, kh, q_held);
  const Eigen::Vector3d g(0, 0, -9.81);
  Eigen::MatrixXd Yf(6, num_standard_parameters(with)), Yh(6, num_standard_parameters(held));
  standard_regressor(with, kf, g, Yf);
  standard_regressor(held, kh, g, Yh);
  EXPECT_TRUE((Yf * nominal_standard_parameters(with))
                  .isApprox(Yh * nominal_standard_parameters(held), 1e-12));
}

std::string load_error(const std::string& xml) {
  try {
    load_urdf_string(xml, "", "m.urdf");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Mimic, ChainsAndCyclesAreNamedAllAtOnce) {
  const std::string link = "<link name=\"L\"><inertial><mass value=\"1\"/></inertial></link>";
  auto joint = [](const std::string& name, const std::string& child, const std::string& mimic) {
    return "<joint name=\"" + name +
           "\" type=\"continuous\"><parent link=\"base\"/><child link=\"" + child +
           "\"/><axis xyz=\"0 0 1\"/>" + (mimic.empty() ? "" : "<mimic joint=\"" + mimic + "\"/>") +
           "</joint>\n";
  };
  std::string xml = "<robot name=\"m\">\n<link name=\"base\"/>\n";
  for (const char* c : {"a", "b", "c", "d", "e"})
    xml += std::regex_replace(link, std::regex("\"L\""), std::string("\"") + c + "\"") + "\n";
  xml += joint("ja", "a", "");
  xml += joint("jb", "b", "jc");  // a cycle: jb -> jc -> jb
  xml += joint("jc", "c", "jb");
  xml += joint("jd", "d", "jb");       // a mimic of a mimic
  xml += joint("je", "e", "nowhere");  // no such joint
  xml += "</robot>\n";
  const std::string e = load_error(xml);
  EXPECT_NE(e.find("4 mimic joints"), std::string::npos) << e;
  for (const char* part : {"'jb' mimics 'jc', which is a mimic joint itself",
                           "'jc' mimics 'jb', which is a mimic joint itself", "'jd' mimics 'jb'",
                           "'je' mimics 'nowhere', which does not exist"})
    EXPECT_NE(e.find(part), std::string::npos) << part << "\n" << e;
  EXPECT_NE(e.find("line "), std::string::npos) << e;
}

TEST(Mimic, PublishedPandaAndRobotiqLoad) {
  const Model panda = load_urdf(kRobotsDir + "panda.urdf");
  EXPECT_EQ(panda.num_joints(), 8);  // 7 arm joints and finger 1; finger 2 mimics it
  ASSERT_EQ(panda.mimics.size(), 1u);
  EXPECT_EQ(panda.mimics[0].name, "panda_finger_joint2");
  EXPECT_EQ(panda.mimics[0].master, "panda_finger_joint1");
  EXPECT_EQ(panda.mimics[0].multiplier, 1.0);  // URDF default

  const Model robotiq = load_urdf(kRobotsDir + "robotiq_2f_85.urdf");
  EXPECT_EQ(robotiq.num_joints(), 1);
  EXPECT_EQ(robotiq.mimics.size(), 5u);
  // Its multiplier -1 fingers have <limit lower="0" upper="0.8757">:
  // taken literally the gripper could not move; the loader says so and keeps
  // the master's range.
  EXPECT_EQ(robotiq.joints[0].lower, 0.0);
  EXPECT_DOUBLE_EQ(robotiq.joints[0].upper, 0.725);  // its own <limit>
  ASSERT_FALSE(robotiq.warnings.empty());
  EXPECT_NE(robotiq.warnings[0].find("ignored"), std::string::npos) << robotiq.warnings[0];
  // Every base parameter the gripper has is identifiable as for any model.
  const BaseParameters base = find_base_parameters(robotiq);
  EXPECT_GT(base.num_unknowns(), 1);
}

TEST(Model, SwappedLimitsAreAnErrorWithTheLine) {
  const std::string xml =
      "<robot name=\"s\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n"
      "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n"
      "<limit lower=\"1.5\" upper=\"-1.5\" effort=\"1\" velocity=\"1\"/></joint>\n</robot>\n";
  const std::string e = load_error(xml);
  EXPECT_NE(e.find("m.urdf:4: joint 'j' has its limits swapped: lower 1.5 > upper -1.5"),
            std::string::npos)
      << e;
}

TEST(Model, UnknownSensorLinkSuggestsTheClosestNames) {
  const std::string e = [] {
    try {
      load_urdf(kRobotsDir + "ur5_robot.urdf", "wrist3_link");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  }();
  EXPECT_NE(e.find("unknown sensor link 'wrist3_link'"), std::string::npos) << e;
  EXPECT_NE(e.find("closest: 'wrist_3_link'"), std::string::npos) << e;
  EXPECT_LT(e.size(), 300u) << e;
}

// An expanded URDF keeps xmlns:xacro and may say "xacro" anywhere in text (the
// TALOS description has "<xacro:include ...>" inside a comment): only an
// element in the xacro namespace makes a xacro file.
TEST(Model, XacroTextInCommentsAndAttributesIsNoXacro) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<!-- generated by xacro from talos.urdf.xacro -->\n"
      "<robot name=\"xacro:robot\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n"
      "<!-- <xacro:include filename=\"$(find talos_description)/urdf/arm.xacro\"/> -->\n"
      "<link name=\"base\"><inertial><mass value=\"2\"/></inertial></link>\n"
      "<link name=\"xacro:arm\"><inertial><mass value=\"1.5\"/></inertial></link>\n"
      "<joint name=\"j_xacro\" type=\"revolute\"><parent link=\"base\"/>"
      "<child link=\"xacro:arm\"/><axis xyz=\"0 0 1\"/>\n"
      "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n</robot>\n";
  const Model m = load_urdf_string(xml, "", "expanded.urdf");
  ASSERT_EQ(m.num_joints(), 1);
  EXPECT_EQ(m.joints[0].name, "j_xacro");
  EXPECT_EQ(m.nominal_total_mass(), 3.5);
  // The namespace under another prefix, and xacro's other URI spelling: refused
  // at the element's line, with the same message.
  const std::string prefixed =
      "<robot name=\"r\">\n<link name=\"a\"/>\n"
      "<group xmlns:x=\"http://ros.org/wiki/xacro\">\n<x:macro name=\"m\"/></group>\n</robot>\n";
  const std::string e = load_error(prefixed);
  EXPECT_NE(e.find("m.urdf:4: this is a xacro file, not a URDF: expand it first (xacro m.urdf > "
                   "robot.urdf)"),
            std::string::npos)
      << e;
  // A prefix declared for another namespace is no xacro.
  EXPECT_EQ(load_error("<robot name=\"r\">\n<link name=\"a\"><gazebo:x "
                       "xmlns:gazebo=\"http://gazebosim.org\"/></link>\n</robot>\n"),
            "no error");
}

TEST(Model, XacroAndFloatingJointsSayWhatToDo) {
  const std::string xacro =
      "<?xml version=\"1.0\"?>\n<robot name=\"r\" xmlns:xacro=\"http://ros.org/wiki/xacro\">\n"
      "<xacro:property name=\"l\" value=\"1\"/>\n<link name=\"a\"/>\n</robot>\n";
  const std::string e = load_error(xacro);
  EXPECT_NE(e.find("m.urdf:3: this is a xacro file, not a URDF: expand it first"),
            std::string::npos)
      << e;
  const std::string floating =
      "<robot name=\"f\">\n<link name=\"world\"/>\n<link name=\"trunk\"/>\n"
      "<joint name=\"floating_base\" type=\"floating\"><parent link=\"world\"/>"
      "<child link=\"trunk\"/></joint>\n</robot>\n";
  const std::string f = load_error(floating);
  EXPECT_NE(f.find("m.urdf:4: joint 'floating_base' is floating"), std::string::npos) << f;
  EXPECT_NE(f.find("sensor link 'trunk'"), std::string::npos) << f;
}

}  // namespace
}  // namespace massid

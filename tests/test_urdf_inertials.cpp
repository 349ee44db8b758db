// The identified URDF: inertials replaced, every other byte kept (urdf_inertials.hpp).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <fstream>
#include <regex>
#include <sstream>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"
#include "massid/identify/urdf_inertials.hpp"
#include "massid/io/urdf.hpp"

namespace massid {
namespace {

// A URDF with what authors put around inertials: a declaration, comments (one
// of them holding a fake <link>), CDATA, <mujoco> and <gazebo> blocks, an
// inertial with a rotated frame and a comment, a link without inertial, a
// self-closing link and attributes in single quotes.
const char* const kUrdf = R"(<?xml version="1.0"?>
<!-- a comment with <link name="base"> inside -->
<robot name="demo">
  <mujoco><compiler fusestatic="false" discardvisual="true"/></mujoco>
  <!-- if mass > 0: <link name="arm"/> -->
  <link name="base">
    <visual><geometry><mesh filename="package://demo/base.stl"/></geometry></visual>
    <inertial>
      <!-- measured by hand -->
      <origin xyz="0 0 0.05" rpy="0 0 0.3"/>
      <mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/>
    </inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link='arm'/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <link name='arm'>
    <collision><geometry><box size="0.1 0.1 0.3"/></geometry></collision>
  </link>
  <joint name="j2" type="fixed">
    <parent link="arm"/><child link="tip"/>
    <origin xyz="0.3 0 0"/>
  </joint>
  <link name="tip"/>
  <gazebo reference="arm"><material><![CDATA[<link name="tip">]]></material></gazebo>
</robot>
)";

LinkInertial inertial(const std::string& link, double mass, const Eigen::Vector3d& com,
                      const Eigen::Vector3d& moments, const std::string& note = "") {
  LinkInertial e;
  e.link = link;
  e.mass = mass;
  e.com = com;
  // A rotated, full inertia tensor (off-diagonal terms written too).
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  e.inertia = r * moments.asDiagonal() * r.transpose();
  e.note = note;
  return e;
}

void expect_link(const Model& model, const LinkInertial& e) {
  const int l = model.find_link(e.link);
  ASSERT_GE(l, 0) << e.link;
  const Link& link = model.links[l];
  EXPECT_TRUE(link.has_inertial) << e.link;
  EXPECT_NEAR(link.mass, e.mass, 1e-15 * e.mass) << e.link;
  EXPECT_LT((link.com - e.com).norm(), 1e-15) << e.link;
  EXPECT_LT((link.inertia - e.inertia).norm(), 1e-15) << e.link;
}

// The text with every <inertial> element (and its line, when alone on it) removed.
std::string without_inertials(const std::string& text) {
  return std::regex_replace(text, std::regex(R"([ \t]*<inertial>[^]*?</inertial>[ \t]*\r?\n?)"),
                            "");
}

TEST(UrdfInertials, ReplacesAndAddsInertialsAndKeepsEveryOtherByte) {
  const std::vector<LinkInertial> edits = {
      inertial("base", 2.5, {0.01, -0.02, 0.04}, {0.011, 0.021, 0.029}, "identified by massid"),
      inertial("arm", 1.2, {0.0, 0.0, 0.15}, {0.009, 0.009, 0.001})};
  const std::string out = replace_inertials(kUrdf, "demo.urdf", edits);

  // Outside the inertials, byte for byte (the comment's fake <link> and the CDATA untouched).
  EXPECT_EQ(without_inertials(out), without_inertials(kUrdf));
  EXPECT_NE(out.find("<!-- a comment with <link name=\"base\"> inside -->"), std::string::npos);
  EXPECT_NE(out.find("<!-- identified by massid -->"), std::string::npos);
  EXPECT_EQ(out.find("measured by hand"), std::string::npos);  // the old element is gone

  // urdfdom reads the new numbers back exactly (shortest round-trip decimals).
  const Model before = load_urdf_string(kUrdf, "", "demo.urdf");
  const Model after = load_urdf_string(out, "", "demo.urdf(out)");
  for (const LinkInertial& e : edits) expect_link(after, e);
  const int tip = after.find_link("tip");
  EXPECT_FALSE(after.links[tip].has_inertial);
  EXPECT_EQ(after.links[tip].mass, before.links[tip].mass);

  // The added element is indented like the link's other children.
  EXPECT_NE(out.find("  <link name='arm'>\n    <collision>"), std::string::npos);
  EXPECT_NE(out.find("\n    <inertial>\n      <origin xyz=\"0 0 0.15\" rpy=\"0 0 0\"/>"),
            std::string::npos)
      << out;
}

TEST(UrdfInertials, SelfClosingLinkAndWindowsLineEndings) {
  const std::string crlf = std::regex_replace(std::string(kUrdf), std::regex("\n"), "\r\n");
  const LinkInertial tip = inertial("tip", 0.3, {0.02, 0.0, 0.0}, {1e-4, 2e-4, 2.5e-4});
  const std::string out = replace_inertials(crlf, "demo.urdf", {tip});
  EXPECT_NE(out.find("  <link name=\"tip\">\r\n    <inertial>\r\n"), std::string::npos) << out;
  EXPECT_NE(out.find("    </inertial>\r\n  </link>\r\n"), std::string::npos) << out;
  EXPECT_EQ(out.find_first_of('\n'), out.find("\r\n") + 1);  // no bare line feed anywhere
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), std::count(out.begin(), out.end(), '\r'));
  expect_link(load_urdf_string(out, "", "crlf.urdf"), tip);
}

TEST(UrdfInertials, MistakesNameTheLinkOrThePlace) {
  const LinkInertial e = inertial("arm", 1.0, {0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(
      {
        try {
          replace_inertials(kUrdf, "demo.urdf", {inertial("elbow", 1.0, {0, 0, 0}, {1, 1, 1})});
        } catch (const InputError& err) {
          EXPECT_NE(std::string(err.what()).find("no link 'elbow'"), std::string::npos);
          throw;
        }
      },
      InputError);
  EXPECT_THROW(replace_inertials(kUrdf, "demo.urdf", {e, e}), InputError);
  try {
    replace_inertials("<robot name=\"x\">\n  <link name=\"a\">\n</robot>\n", "bad.urdf", {e});
    FAIL() << "an unbalanced file was accepted";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("bad.urdf:3:1"), std::string::npos) << err.what();
  }
}

// The published robots: every link rewritten, reloaded, nothing else changed.
TEST(UrdfInertials, PublishedRobotsReloadWithTheNewInertials) {
  for (const char* name : {"ur5_robot", "panda", "robotiq_2f_85"}) {
    const std::string path = std::string(MASSID_SOURCE_DIR "/tests/data/robots/") + name + ".urdf";
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const Model model = load_urdf(path);
    std::vector<LinkInertial> edits;
    for (int l = 0; l < model.num_links(); ++l)
      edits.push_back(inertial(model.links[l].name, 1.0 + 0.1 * l, {0.01 * l, 0.002, -0.003},
                               {0.02, 0.03, 0.04}));
    const std::string out = replace_inertials(text.str(), path, edits);
    // (The UR5's <link name="world"/> opens to hold its inertial.)
    const auto closed = [](const std::string& t) {
      return std::regex_replace(without_inertials(t), std::regex(R"((<link [^>]*[^/])>\s*</link>)"),
                                "$1/>");
    };
    EXPECT_TRUE(closed(out) == closed(text.str())) << name;
    const Model after = load_urdf_string(out, "", path);
    ASSERT_EQ(after.num_links(), model.num_links()) << name;
    for (const LinkInertial& e : edits) expect_link(after, e);
    // Everything but the inertials: joints and their frames as before.
    for (int j = 0; j < model.num_joints(); ++j) {
      EXPECT_EQ(after.joints[j].name, model.joints[j].name);
      EXPECT_EQ(after.joints[j].lower, model.joints[j].lower);
    }
    for (int l = 0; l < model.num_links(); ++l)
      EXPECT_TRUE(after.links[l].origin.isApprox(model.links[l].origin, 0.0)) << name;
  }
}

}  // namespace
}  // namespace massid

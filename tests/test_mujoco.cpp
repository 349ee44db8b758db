// Cross-check of massid::simulate_wrenches against MuJoCo's force/torque sensor.
//
// For every example robot and every row of its plan, the static wrench that the
// measured bodies exert on the sensor is computed twice:
//
//   massid: simulate_wrenches (no noise, no offset);
//   MuJoCo: a <force> and a <torque> sensor on a site at the sensor link's
//           origin. The sensor link is welded (no joint) to a body "mount" that
//           is fixed to the world in a deliberately non-trivial pose, so the
//           sensor frame is not the world frame and gravity has to be rotated
//           into the world: g_world = R_mount g_sensor. The joints are held
//           (qvel = 0, qfrc_applied = qfrc_bias, hence qacc = 0) and MuJoCo's
//           reading, the force the mount exerts on the sensor link's subtree, is
//           negated to give the load on the sensor (interface.md).
//
// The MuJoCo model is built in two ways:
//
//   Generated:  MJCF written by this test from massid's Model (link origins,
//               joint axes, masses, centres of mass) with 17 significant digits.
//               Checks the static wrench (kinematics, sign, frame, moment point)
//               given massid's reading of the URDF.
//   Imported:   the URDF itself loaded by MuJoCo's own URDF importer (with
//               fusestatic="false" so that the root link and the fixed links
//               keep their bodies and masses). Its numbers (body frames,
//               inertial frames, masses, joint axes) are copied, matched by
//               name, into the generated model with its mount, site and sensors
//               (mj_saveLastXML would round them to 6 digits). This also checks
//               massid's URDF parsing (rpy convention, axis normalisation,
//               inertial origins) against an independent parser.
//
// Tolerance: 1e-9 absolute, in N and N m, on every component. The wrenches are
// O(1..300) N and O(0.1..100) N m; both sides compute them in double precision
// with round-off near 1e-13, so 1e-9 leaves a wide margin, while any modelling
// difference (a 6-digit rounding of a length or an angle already gives ~1e-5)
// fails by orders of magnitude. An absolute bound is stricter than a relative
// one here since every wrench magnitude exceeds 1.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/urdf_inertials.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "mujoco_support.hpp"

namespace {

using namespace massid::mujoco_test;

constexpr double kTolerance = 1e-9;  // N and N m, absolute, per component

// The mount: where the sensor sits in the world. Not the identity on purpose.
Eigen::Isometry3d mount_pose() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).matrix();
  t.translation() = Eigen::Vector3d(0.3, -0.2, 0.5);
  return t;
}

void emit_body(const massid::Model& model, int index, int depth, std::ostringstream& x) {
  const massid::Link& link = model.links[static_cast<std::size_t>(index)];
  const std::string pad(static_cast<std::size_t>(2 * depth), ' ');
  x << pad << "<body name=\"" << link.name << "\" pos=\"" << vec(link.origin.translation())
    << "\" quat=\"" << quat(link.origin.linear()) << "\">\n";
  if (link.type != massid::JointType::Fixed) {
    x << pad << "  <joint name=\"" << link.joint << "\" type=\""
      << (link.type == massid::JointType::Revolute ? "hinge" : "slide") << "\" axis=\""
      << vec(link.axis) << "\" pos=\"0 0 0\"/>\n";
  }
  if (link.mass > 0.0) {
    // The inertia does not enter a static wrench; any valid one will do.
    const double i = 1e-3 * link.mass;
    x << pad << "  <inertial pos=\"" << vec(link.com) << "\" mass=\"" << num(link.mass)
      << "\" diaginertia=\"" << num(i) << " " << num(i) << " " << num(i) << "\"/>\n";
  }
  if (index == 0) x << pad << "  <site name=\"ft\" pos=\"0 0 0\" quat=\"1 0 0 0\"/>\n";
  for (int child = 0; child < model.num_links(); ++child) {
    if (model.links[static_cast<std::size_t>(child)].parent == index) {
      emit_body(model, child, depth + 1, x);
    }
  }
  x << pad << "</body>\n";
}

// MJCF of the measured bodies from massid's Model, on a mount fixed to the world,
// with a force and a torque sensor at the sensor link's origin.
std::string mjcf_from_model(const massid::Model& model) {
  const Eigen::Isometry3d mount = mount_pose();
  std::ostringstream x;
  x << "<mujoco model=\"" << model.name << "\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "  <option gravity=\"0 0 0\"/>\n"
    << "  <worldbody>\n"
    << "    <body name=\"massid_mount\" pos=\"" << vec(mount.translation()) << "\" quat=\""
    << quat(mount.linear()) << "\">\n";
  emit_body(model, 0, 3, x);
  x << "    </body>\n"
    << "  </worldbody>\n"
    << "  <sensor>\n"
    << "    <force name=\"ft_force\" site=\"ft\"/>\n"
    << "    <torque name=\"ft_torque\" site=\"ft\"/>\n"
    << "  </sensor>\n"
    << "</mujoco>\n";
  return x.str();
}

// The load on the sensor (negated MuJoCo reading) at every plan row: [N x 6].
Eigen::MatrixXd mujoco_wrenches(mjModel* m, const massid::Model& model,
                                const massid::Samples& samples) {
  if (m->nq != model.num_joints() || m->nv != model.num_joints()) {
    throw std::runtime_error("MuJoCo model has other degrees of freedom than massid's");
  }
  std::vector<int> qadr;
  for (const massid::Joint& joint : model.joints) {
    qadr.push_back(m->jnt_qposadr[id_of(m, mjOBJ_JOINT, joint.name)]);
  }
  const int force = id_of(m, mjOBJ_SENSOR, "ft_force");
  const int torque = id_of(m, mjOBJ_SENSOR, "ft_torque");
  if (m->sensor_type[force] != mjSENS_FORCE || m->sensor_type[torque] != mjSENS_TORQUE) {
    throw std::runtime_error("unexpected sensor types");
  }
  const int sensor_body = id_of(m, mjOBJ_BODY, model.sensor_link());
  if (m->body_jntnum[sensor_body] != 0) throw std::runtime_error("sensor link is not welded");

  // Nothing but gravity and the holding forces: no contacts, limits, springs.
  m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;

  const Eigen::Matrix3d r_mount = mount_pose().linear();
  DataPtr d(mj_makeData(m));
  Eigen::MatrixXd w(samples.size(), 6);
  for (int i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d g_sensor = samples.gravity.row(i).transpose();
    const Eigen::Vector3d g_world = r_mount * g_sensor;
    for (int k = 0; k < 3; ++k) m->opt.gravity[k] = g_world[k];
    mj_resetData(m, d.get());
    for (int j = 0; j < model.num_joints(); ++j) {
      d->qpos[qadr[static_cast<std::size_t>(j)]] = samples.q(i, j);
    }
    mju_zero(d->qvel, m->nv);
    mj_forward(m, d.get());
    // Hold the arm: the applied joint forces cancel gravity, so qacc = 0.
    mju_copy(d->qfrc_applied, d->qfrc_bias, m->nv);
    mj_forward(m, d.get());
    for (int k = 0; k < m->nv; ++k) {
      if (std::abs(d->qacc[k]) > 1e-12) {
        throw std::runtime_error("arm not held at row " + std::to_string(i) +
                                 ": qacc = " + num(d->qacc[k]));
      }
    }
    for (int k = 0; k < 3; ++k) {
      w(i, k) = -d->sensordata[m->sensor_adr[force] + k];
      w(i, 3 + k) = -d->sensordata[m->sensor_adr[torque] + k];
    }
  }
  return w;
}

struct Robot {
  const char* name;
  const char* urdf;
  const char* plan;
};

void PrintTo(const Robot& robot, std::ostream* os) { *os << robot.name; }

struct Comparison {
  double max_abs = 0.0;     // largest |MuJoCo - massid| over all rows and components
  double max_rel = 0.0;     // largest row-wise |difference| / |wrench|
  double max_wrench = 0.0;  // largest |wrench| component, to show the scale
  int worst_row = -1;
};

Comparison compare(const Eigen::MatrixXd& mujoco, const Eigen::MatrixXd& massid_w) {
  Comparison c;
  for (int i = 0; i < mujoco.rows(); ++i) {
    const double diff = (mujoco.row(i) - massid_w.row(i)).cwiseAbs().maxCoeff();
    if (diff > c.max_abs || c.worst_row < 0) {
      c.max_abs = diff;
      c.worst_row = i;
    }
    c.max_rel = std::max(c.max_rel, (mujoco.row(i) - massid_w.row(i)).norm() /
                                        std::max(massid_w.row(i).norm(), 1e-300));
    c.max_wrench = std::max(c.max_wrench, massid_w.row(i).cwiseAbs().maxCoeff());
  }
  return c;
}

class MujocoCrossCheck : public ::testing::TestWithParam<Robot> {
 protected:
  void SetUp() override {
    const Robot& robot = GetParam();
    urdf_path_ = std::string(MASSID_SOURCE_DIR) + "/" + robot.urdf;
    model_ = massid::load_urdf(urdf_path_);
    ASSERT_EQ(model_.sensor_link(), "sensor");
    samples_ = massid::read_samples(
        model_, massid::read_csv(std::string(MASSID_SOURCE_DIR) + "/" + robot.plan),
        massid::WrenchColumns::Optional);
    ASSERT_GT(samples_.size(), 0);
    expected_ = massid::simulate_wrenches(model_, samples_);
    ASSERT_EQ(expected_.rows(), samples_.size());
    ASSERT_EQ(expected_.cols(), 6);
    // Not a vacuous comparison: every row carries the full weight.
    for (int i = 0; i < samples_.size(); ++i) {
      ASSERT_GT(expected_.row(i).head<3>().norm(), 1.0) << "row " << i;
    }
  }

  void check(const char* variant, const Eigen::MatrixXd& mujoco) {
    ASSERT_EQ(mujoco.rows(), expected_.rows());
    const Comparison c = compare(mujoco, expected_);
    std::cout << "[ mujoco   ] " << GetParam().name << " (" << variant << "): rows "
              << samples_.size() << ", max |wrench| " << num(c.max_wrench)
              << ", max |MuJoCo - massid| " << num(c.max_abs) << " (row " << c.worst_row
              << "), max relative " << num(c.max_rel) << "\n";
    RecordProperty(std::string(variant) + "_max_abs_diff", num(c.max_abs));
    for (int i = 0; i < mujoco.rows(); ++i) {
      for (int k = 0; k < 6; ++k) {
        EXPECT_NEAR(mujoco(i, k), expected_(i, k), kTolerance)
            << variant << ": row " << i << " (file line "
            << samples_.line[static_cast<std::size_t>(i)] << "), component "
            << massid::kWrenchColumns[k];
      }
    }
  }

  std::string urdf_path_;
  massid::Model model_;
  massid::Samples samples_;
  Eigen::MatrixXd expected_;
};

TEST_P(MujocoCrossCheck, GeneratedMjcfMatchesSimulate) {
  TempDir dir(std::string(GetParam().name) + "_generated");
  const fs::path path = dir.path() / "model.xml";
  write_text(path, mjcf_from_model(model_));
  ModelPtr m = load_mujoco(path);
  // The measured bodies carry the URDF's total mass.
  const int sensor_body = id_of(m.get(), mjOBJ_BODY, model_.sensor_link());
  EXPECT_NEAR(m->body_subtreemass[sensor_body], model_.nominal_total_mass(), 1e-12);
  check("generated", mujoco_wrenches(m.get(), model_, samples_));
}

TEST_P(MujocoCrossCheck, ImportedUrdfMatchesSimulate) {
  TempDir dir(std::string(GetParam().name) + "_imported");
  const fs::path urdf = dir.path() / "robot.urdf";
  write_text(urdf, urdf_for_mujoco(read_text(urdf_path_)));
  ModelPtr imported = load_mujoco(urdf);
  const fs::path path = dir.path() / "model.xml";
  write_text(path, mjcf_from_model(model_));
  ModelPtr m = load_mujoco(path);
  const double change = copy_imported_numbers(model_, imported.get(), m.get());
  std::cout << "[ mujoco   ] " << GetParam().name
            << ": largest difference between MuJoCo's and massid's reading of the URDF "
            << num(change) << "\n";
  // MuJoCo's importer keeps every link's mass, the root's too.
  const int root = id_of(imported.get(), mjOBJ_BODY, model_.sensor_link());
  EXPECT_EQ(imported->body_parentid[root], 0);
  EXPECT_NEAR(imported->body_subtreemass[root], model_.nominal_total_mass(), 1e-12);
  check("imported", mujoco_wrenches(m.get(), model_, samples_));
}

// The identified URDF (urdf_inertials.hpp) as MuJoCo's own importer reads it:
// every link's new mass, centre of mass and full inertia tensor (rebuilt from
// MuJoCo's principal moments and axes).
TEST_P(MujocoCrossCheck, RewrittenInertialsImportWithTheirNumbers) {
  std::vector<massid::LinkInertial> edits;
  for (int l = 0; l < model_.num_links(); ++l) {
    const massid::Link& link = model_.links[l];
    massid::LinkInertial e;
    e.link = link.name;
    e.mass = 0.5 + 1.1 * link.mass;
    e.com = link.com + Eigen::Vector3d(0.01, -0.02, 0.005 * l);
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(0.3 + l, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).matrix();
    e.inertia = r * Eigen::Vector3d(0.02, 0.03, 0.045).asDiagonal() * r.transpose();
    e.note = "test";
    edits.push_back(e);
  }
  TempDir dir(std::string(GetParam().name) + "_rewritten");
  const fs::path urdf = dir.path() / "robot.urdf";
  write_text(urdf,
             urdf_for_mujoco(massid::replace_inertials(read_text(urdf_path_), urdf_path_, edits)));
  ModelPtr m = load_mujoco(urdf);
  for (const massid::LinkInertial& e : edits) {
    const int b = id_of(m.get(), mjOBJ_BODY, e.link);
    EXPECT_NEAR(m->body_mass[b], e.mass, 1e-14) << e.link;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m->body_ipos[3 * b + k], e.com[k], 1e-15) << e.link;
    const mjtNum* q = m->body_iquat + 4 * b;
    const Eigen::Matrix3d axes = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    const Eigen::Vector3d moments(m->body_inertia[3 * b], m->body_inertia[3 * b + 1],
                                  m->body_inertia[3 * b + 2]);
    const Eigen::Matrix3d inertia = axes * moments.asDiagonal() * axes.transpose();
    // MuJoCo diagonalises a full tensor iteratively (mju_eig3): ~1e-7 relative.
    EXPECT_LT((inertia - e.inertia).norm(), 1e-6 * e.inertia.norm()) << e.link;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Examples, MujocoCrossCheck,
    ::testing::Values(
        Robot{"puma260", "examples/puma260/puma260.urdf", "examples/puma260/plan.csv"},
        Robot{"ur_like", "examples/ur_like/ur_like.urdf", "examples/ur_like/plan.csv"},
        Robot{"branching", "examples/branching/branching.urdf", "examples/branching/plan.csv"},
        Robot{"wrist_tool", "examples/wrist_tool/wrist_tool.urdf", "examples/wrist_tool/plan.csv"}),
    [](const ::testing::TestParamInfo<Robot>& info) { return std::string(info.param.name); });

}  // namespace

// Side-by-side anchors for the gravity wrench at the base, on the same robots
// and samples as massid's predictor (BM_Predict in bench_core.cpp):
//
//   BM_KdlFkWrench    orocos KDL forward kinematics of every segment, then
//                     f = M g, m = sum_i c_i x m_i g (what a user writes with KDL)
//   BM_KdlRneWrench   KDL's recursive Newton-Euler on the chain behind six
//                     virtual root joints (Tx Ty Tz Rx Ry Rz): their torques at
//                     rest are the support wrench
//   BM_MujocoWrench   MuJoCo with the joints held: mj_kinematics, mj_comPos,
//                     mj_sensorAcc on a force/torque sensor at the sensor link
//
// and for the full wrench in motion (weight and inertial forces; joints with
// random velocities and accelerations), against massid's motion predictor:
//
//   BM_PredictMotionAnchor  massid predict_motion (motion_predictor.hpp) from
//                     the dynamic base parameters of the URDF's inertials
//   BM_KdlRneMotionWrench   KDL's ChainIdSolver_RNE on the same chain behind
//                     the six virtual root joints, held (q = qd = qdd = 0),
//                     the robot's joints moving: their torques are the wrench
//
// The KDL chain is built from the URDF (through massid::Model, which urdfdom
// loads) as kdl_parser does: one segment per link, the joint at the segment's
// origin, the link's inertia in the segment's tip frame. Serial robots only
// (KDL chains). Each benchmark first checks that its wrench equals massid's
// (simulate_wrenches from the URDF's inertials, at rest or in motion) to 1e-9
// relative, and reports an error instead of a time if not.
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <kdl/chain.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <random>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/emulator/mujoco_plant.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid;

const char* const kSerialRobots[] = {MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf",
                                     MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf"};
const char* const kSerialNames[] = {"puma260", "ur_like"};
const Eigen::Vector3d kGravity = 9.80665 * Eigen::Vector3d(0.3, -0.2, -1.0).normalized();

KDL::Vector kdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
KDL::Frame kdl(const Eigen::Isometry3d& t) {
  const Eigen::Matrix3d& r = t.linear();
  return KDL::Frame(KDL::Rotation(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0),
                                  r(2, 1), r(2, 2)),
                    kdl(t.translation()));
}

// One segment per link below the sensor link, kdl_parser style. Throws unless serial.
KDL::Chain kdl_chain(const Model& model, bool virtual_root) {
  KDL::Chain chain;
  if (virtual_root) {
    const KDL::Joint::JointType types[] = {KDL::Joint::TransX, KDL::Joint::TransY,
                                           KDL::Joint::TransZ, KDL::Joint::RotX,
                                           KDL::Joint::RotY,   KDL::Joint::RotZ};
    for (const auto type : types) chain.addSegment(KDL::Segment(KDL::Joint(type)));
  }
  const auto inertia = [](const Link& l) {
    const Eigen::Matrix3d& i = l.inertia;
    return KDL::RigidBodyInertia(
        l.mass, kdl(l.com),
        KDL::RotationalInertia(i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2)));
  };
  // The sensor link itself: a fixed segment at the chain's root.
  chain.addSegment(KDL::Segment(model.links[0].name, KDL::Joint(KDL::Joint::None),
                                KDL::Frame::Identity(), inertia(model.links[0])));
  for (int l = 1; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    if (link.parent != l - 1) throw std::runtime_error("KDL anchor: not a serial chain");
    const KDL::Frame origin = kdl(link.origin);
    KDL::Joint joint(link.name + "_joint", KDL::Joint::None);
    if (link.type == JointType::Revolute)
      joint = KDL::Joint(link.joint, origin.p, origin.M * kdl(link.axis), KDL::Joint::RotAxis);
    if (link.type == JointType::Prismatic)
      joint = KDL::Joint(link.joint, origin.p, origin.M * kdl(link.axis), KDL::Joint::TransAxis);
    chain.addSegment(KDL::Segment(link.name, joint, origin, inertia(link)));
  }
  return chain;
}

struct Fixture {
  Model model;
  std::vector<Eigen::VectorXd> q;        // 1024 random joint positions
  std::vector<Eigen::VectorXd> qd, qdd;  // and velocities, accelerations (motion anchors)
  explicit Fixture(int robot) : model(load_urdf(kSerialRobots[robot])) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 1024; ++i) {
      Eigen::VectorXd v(model.num_joints());
      for (int j = 0; j < model.num_joints(); ++j) v[j] = model.joints[j].generic_position(u(rng));
      q.push_back(v);
    }
    std::normal_distribution<double> n;
    for (int i = 0; i < 1024; ++i) {
      Eigen::VectorXd v(model.num_joints()), a(model.num_joints());
      for (int j = 0; j < model.num_joints(); ++j) v[j] = 2.0 * n(rng), a[j] = 5.0 * n(rng);
      qd.push_back(v);
      qdd.push_back(a);
    }
  }
  Wrench truth(int i, bool motion) const {
    const auto k = static_cast<std::size_t>(i);
    Samples s;
    s.q = q[k].transpose();
    s.gravity = kGravity.transpose();
    SimulateOptions o;
    if (motion) {
      s.qd = qd[k].transpose();
      s.qdd = qdd[k].transpose();
      o.dynamic = true;
    }
    return simulate_wrenches(model, s, o).row(0).transpose();
  }
  // Checks an anchor against massid on 16 samples; false (and the error set) if off.
  template <typename F>
  bool agrees(benchmark::State& state, F&& wrench, bool motion = false) const {
    for (int i = 0; i < 16; ++i) {
      const Wrench expected = truth(i, motion), got = wrench(i);
      if ((got - expected).norm() > 1e-9 * expected.norm()) {
        state.SkipWithError(motion ? "anchor disagrees with massid's wrench in motion"
                                   : "anchor disagrees with massid's gravity wrench");
        return false;
      }
    }
    return true;
  }
};

// Joint positions in KDL's order: the chain's movable joints are the model's.
void to_kdl(const Eigen::VectorXd& q, KDL::JntArray& out, int first) {
  for (Eigen::Index j = 0; j < q.size(); ++j) out(static_cast<unsigned>(first + j)) = q[j];
}

void BM_KdlFkWrench(benchmark::State& state) {
  const Fixture fx(static_cast<int>(state.range(0)));
  const KDL::Chain chain = kdl_chain(fx.model, false);
  KDL::JntArray q(chain.getNrOfJoints());
  const KDL::Vector g = kdl(kGravity);
  double total_mass = 0.0;
  for (const auto& s : chain.segments) total_mass += s.getInertia().getMass();
  const auto wrench = [&](int i) {
    to_kdl(fx.q[static_cast<std::size_t>(i)], q, 0);
    KDL::Frame frame = KDL::Frame::Identity();
    KDL::Vector first_moment = KDL::Vector::Zero();
    unsigned j = 0;
    for (const KDL::Segment& s : chain.segments) {
      frame = frame * s.pose(s.getJoint().getType() == KDL::Joint::None ? 0.0 : q(j++));
      first_moment += s.getInertia().getMass() * (frame * s.getInertia().getCOG());
    }
    Wrench w;
    const KDL::Vector f = total_mass * g, m = first_moment * g;
    w << f.x(), f.y(), f.z(), m.x(), m.y(), m.z();
    return w;
  };
  if (!fx.agrees(state, wrench)) return;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(wrench(i));
    i = (i + 1) & 1023;
  }
  state.SetLabel(kSerialNames[state.range(0)]);
}
BENCHMARK(BM_KdlFkWrench)->DenseRange(0, 1);

void BM_KdlRneWrench(benchmark::State& state) {
  const Fixture fx(static_cast<int>(state.range(0)));
  const KDL::Chain chain = kdl_chain(fx.model, true);
  const unsigned n = chain.getNrOfJoints();
  KDL::ChainIdSolver_RNE solver(chain, kdl(kGravity));
  KDL::JntArray q(n), zero(n), tau(n);
  KDL::Wrenches external(chain.getNrOfSegments(), KDL::Wrench::Zero());
  const auto wrench = [&](int i) {
    to_kdl(fx.q[static_cast<std::size_t>(i)], q, 6);
    solver.CartToJnt(q, zero, zero, external, tau);
    Wrench w;  // the support wrench is minus the load's wrench on the sensor
    for (int k = 0; k < 6; ++k) w[k] = -tau(static_cast<unsigned>(k));
    return w;
  };
  if (!fx.agrees(state, wrench)) return;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(wrench(i));
    i = (i + 1) & 1023;
  }
  state.SetLabel(kSerialNames[state.range(0)]);
}
BENCHMARK(BM_KdlRneWrench)->DenseRange(0, 1);

void BM_PredictMotionAnchor(benchmark::State& state) {
  const Fixture fx(static_cast<int>(state.range(0)));
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  const BaseParameters base = find_base_parameters(fx.model, o);
  const MotionPredictor pred =
      compile_motion_predictor(fx.model, base, base.K * o.layout.nominal(fx.model));
  MotionPredictorData data(pred);
  const auto wrench = [&](int i) {
    const auto k = static_cast<std::size_t>(i);
    return predict_motion(pred, data, fx.q[k].data(), fx.qd[k].data(), fx.qdd[k].data(), kGravity);
  };
  if (!fx.agrees(state, wrench, true)) return;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(wrench(i));
    i = (i + 1) & 1023;
  }
  state.SetLabel(kSerialNames[state.range(0)]);
}
BENCHMARK(BM_PredictMotionAnchor)->DenseRange(0, 1);

void BM_KdlRneMotionWrench(benchmark::State& state) {
  const Fixture fx(static_cast<int>(state.range(0)));
  const KDL::Chain chain = kdl_chain(fx.model, true);
  const unsigned n = chain.getNrOfJoints();
  KDL::ChainIdSolver_RNE solver(chain, kdl(kGravity));
  KDL::JntArray q(n), qd(n), qdd(n), tau(n);
  KDL::Wrenches external(chain.getNrOfSegments(), KDL::Wrench::Zero());
  const auto wrench = [&](int i) {
    const auto k = static_cast<std::size_t>(i);
    to_kdl(fx.q[k], q, 6);
    to_kdl(fx.qd[k], qd, 6);
    to_kdl(fx.qdd[k], qdd, 6);
    solver.CartToJnt(q, qd, qdd, external, tau);
    Wrench w;  // the support wrench is minus the load's wrench on the sensor
    for (int c = 0; c < 6; ++c) w[c] = -tau(static_cast<unsigned>(c));
    return w;
  };
  if (!fx.agrees(state, wrench, true)) return;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(wrench(i));
    i = (i + 1) & 1023;
  }
  state.SetLabel(kSerialNames[state.range(0)]);
}
BENCHMARK(BM_KdlRneMotionWrench)->DenseRange(0, 1);

void BM_MujocoWrench(benchmark::State& state) {
  const Fixture fx(static_cast<int>(state.range(0)));
  const std::string xml =
      "<mujoco><compiler angle=\"radian\" inertiafromgeom=\"false\"/>"
      "<option><flag contact=\"disable\" constraint=\"disable\"/></option><worldbody>" +
      emulator::robot_mjcf(fx.model, {}, Eigen::Isometry3d::Identity(), 0) +
      "</worldbody><sensor><force site=\"massid_ft\"/><torque site=\"massid_ft\"/></sensor>"
      "</mujoco>";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "anchor.xml", static_cast<int>(xml.size()));
  std::copy(xml.begin(), xml.end(),
            static_cast<char*>(vfs.filedata[mj_findFileVFS(&vfs, "anchor.xml")]));
  char error[500] = "";
  mjModel* m = mj_loadXML("anchor.xml", &vfs, error, sizeof(error));
  mj_deleteVFS(&vfs);
  if (!m) {
    state.SkipWithError(error);
    return;
  }
  mjData* d = mj_makeData(m);
  for (int k = 0; k < 3; ++k) m->opt.gravity[k] = kGravity[k];
  mj_forward(m, d);  // velocities stay zero
  const auto wrench = [&](int i) {
    const Eigen::VectorXd& q = fx.q[static_cast<std::size_t>(i)];
    for (int j = 0; j < m->nq; ++j) d->qpos[j] = q[j];
    mju_zero(d->qacc, m->nv);  // joints held
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_sensorAcc(m, d);
    Wrench w;  // MuJoCo reports the parent's wrench on the child: negate
    for (int k = 0; k < 6; ++k) w[k] = -d->sensordata[k];
    return w;
  };
  if (fx.agrees(state, wrench)) {
    int i = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(wrench(i));
      i = (i + 1) & 1023;
    }
    state.SetLabel(kSerialNames[state.range(0)]);
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}
BENCHMARK(BM_MujocoWrench)->DenseRange(0, 1);

}  // namespace

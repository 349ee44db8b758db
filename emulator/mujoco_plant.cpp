#include "massid/emulator/mujoco_plant.hpp"

#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <locale>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "massid/core/errors.hpp"

namespace massid::emulator {

namespace {

// Full precision: 17 significant digits read back to the same double.
std::string num(double v) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s << std::setprecision(17) << v;
  return s.str();
}

std::string vec(const Eigen::Vector3d& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}

std::string quat(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

std::string pose_attributes(const Eigen::Isometry3d& t) {
  return "pos=\"" + vec(t.translation()) + "\" quat=\"" + quat(t.linear()) + "\"";
}

// <inertial> of mass `mass`, com `com`, inertia `inertia` about the com (body frame).
std::string inertial(const Eigen::Vector3d& com, double mass, const Eigen::Matrix3d& inertia) {
  const Eigen::Matrix3d i = 0.5 * (inertia + inertia.transpose());
  return "<inertial pos=\"" + vec(com) + "\" mass=\"" + num(mass) + "\" fullinertia=\"" +
         num(i(0, 0)) + " " + num(i(1, 1)) + " " + num(i(2, 2)) + " " + num(i(0, 1)) + " " +
         num(i(0, 2)) + " " + num(i(1, 2)) + "\"/>";
}

// The link's URDF inertia when MuJoCo can take it (symmetric positive definite,
// principal moments obeying the triangle inequality), else an isotropic one.
Eigen::Matrix3d plant_inertia(const Link& link, const PlantOptions& options) {
  const Eigen::Matrix3d i = 0.5 * (link.inertia + link.inertia.transpose());
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(i, Eigen::EigenvaluesOnly).eigenvalues();
  const double floor = 1e-9 * link.mass;  // kg m^2: a 30 um radius of gyration
  if (i.allFinite() && moments[0] > floor && moments[0] + moments[1] >= moments[2]) return i;
  const double r = options.default_radius_of_gyration;
  return Eigen::Matrix3d::Identity() * link.mass * r * r;
}

void emit_body(const Model& model, const PlantOptions& options, int index,
               const Eigen::Isometry3d& pose, int indent, std::ostringstream& x) {
  const Link& link = model.links[static_cast<std::size_t>(index)];
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  x << pad << "<body name=\"" << mjcf_body_name(link.name) << "\" " << pose_attributes(pose)
    << ">\n";
  if (link.type != JointType::Fixed) {
    // A mimic link gets a joint of its own too, named after the mimic joint
    // (URDF joint names are unique); the plant drives it with its master.
    x << pad << "  <joint name=\"" << mjcf_joint_name(link.joint) << "\" type=\""
      << (link.type == JointType::Revolute ? "hinge" : "slide") << "\" axis=\"" << vec(link.axis)
      << "\" pos=\"0 0 0\" limited=\"false\"/>\n";
  }
  if (link.mass > 0.0)
    x << pad << "  " << inertial(link.com, link.mass, plant_inertia(link, options)) << "\n";
  if (index == 0) x << pad << "  <site name=\"massid_ft\" pos=\"0 0 0\" quat=\"1 0 0 0\"/>\n";
  for (int child = 0; child < model.num_links(); ++child) {
    const Link& c = model.links[static_cast<std::size_t>(child)];
    if (c.parent == index) emit_body(model, options, child, c.origin, indent + 2, x);
  }
  x << pad << "</body>\n";
}

void check_options(const Model& model, const PlantOptions& o) {
  const auto positive = [](double v, const char* what) {
    if (!(std::isfinite(v) && v > 0.0)) {
      throw InputError(fmt::format("plant option {} must be positive and finite, not {}", what, v));
    }
  };
  positive(o.timestep, "timestep");
  positive(o.platform_mass, "platform_mass");
  positive(o.platform_kp, "platform_kp");
  positive(o.platform_kd, "platform_kd");
  positive(o.joint_kp, "joint_kp");
  positive(o.joint_kd, "joint_kd");
  positive(o.default_radius_of_gyration, "default_radius_of_gyration");
  if (!o.gravity.allFinite()) throw InputError("plant option gravity is not finite");
  if (model.num_links() == 0) throw InputError("the model has no links");
}

std::string options_xml(double timestep, const Eigen::Vector3d& gravity) {
  return "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n  <option timestep=\"" +
         num(timestep) + "\" integrator=\"RK4\" gravity=\"" + vec(gravity) +
         "\">\n    <flag contact=\"disable\" constraint=\"disable\"/>\n  </option>\n";
}

const char* const kSensorsXml =
    "  <sensor>\n"
    "    <force name=\"massid_ft_force\" site=\"massid_ft\"/>\n"
    "    <torque name=\"massid_ft_torque\" site=\"massid_ft\"/>\n"
    "  </sensor>\n";

Eigen::Vector3d rotation_log(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
struct VfsDeleter {
  void operator()(mjVFS* v) const {
    mj_deleteVFS(v);
    delete v;
  }
};

}  // namespace

std::string mjcf_body_name(const std::string& link) {
  for (const char* reserved : {"world", "massid_platform", "massid_spacecraft"})
    if (link == reserved) return "massid_link_" + link;
  return link;
}

std::string mjcf_joint_name(const std::string& joint) {
  for (const char* reserved : {"massid_platform_free", "massid_spacecraft_free"})
    if (joint == reserved) return "massid_joint_" + joint;
  return joint;
}

std::string robot_mjcf(const Model& model, const PlantOptions& options,
                       const Eigen::Isometry3d& parent_T_sensor, int indent) {
  check_options(model, options);
  std::ostringstream x;
  emit_body(model, options, 0, parent_T_sensor, indent, x);
  return x.str();
}

std::string mimic_equalities_mjcf(const Model& model, int indent) {
  if (model.mimics.empty()) return "";
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  std::ostringstream x;
  x << pad << "<equality>\n";
  // joint1 - qpos0_1 = polycoef[0] + polycoef[1] (joint2 - qpos0_2) + ...; the
  // reference positions qpos0 are 0 (no ref attribute), so in absolute terms
  // q_mimic = offset + multiplier q_master, the URDF's <mimic>.
  for (const MimicJoint& m : model.mimics)
    x << pad << "  <joint joint1=\"" << mjcf_joint_name(m.name) << "\" joint2=\""
      << mjcf_joint_name(m.master) << "\" polycoef=\"" << num(m.offset) << " " << num(m.multiplier)
      << " 0 0 0\"/>\n";
  x << pad << "</equality>\n";
  return x.str();
}

// The MuJoCo model and data, the servo laws and the stepping protocol. mjData
// is brought up to date lazily (Stage): a reader gets the current state under
// the servo forces of the commands now in effect, and nothing is computed
// twice or for nobody (per 1 ms control tick: the sensors once, four
// Runge-Kutta stages, the kinematics for the poses).
class MujocoSimulation {
 public:
  MujocoSimulation(const Model& model, const std::string& xml, const char* free_body,
                   bool platform_servo, const PlantOptions& options)
      : options_(options), platform_servo_(platform_servo) {
    std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
    mj_defaultVFS(vfs.get());
    const char* name = "massid_plant.xml";
    if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
      throw InputError("MuJoCo: cannot make a virtual file for the plant model");
    }
    const int file = mj_findFileVFS(vfs.get(), name);
    std::memcpy(vfs->filedata[file], xml.data(), xml.size());
    char error[1000] = "";
    m_.reset(mj_loadXML(name, vfs.get(), error, sizeof(error)));
    if (!m_) throw InputError(fmt::format("MuJoCo rejects the plant model: {}", error));
    m_->opt.timestep = options.timestep;
    m_->opt.integrator = mjINT_RK4;
    m_->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_CONSTRAINT;
    d_.reset(mj_makeData(m_.get()));
    if (!d_) throw InputError("MuJoCo cannot allocate the plant's data");

    const auto id = [this](int type, const std::string& n) {
      const int i = mj_name2id(m_.get(), type, n.c_str());
      if (i < 0) throw InputError("MuJoCo plant model has no object named " + n);
      return i;
    };
    // Driven joints: the independent ones (Model::joints order), then the
    // mimic joints, each following its master.
    const auto add = [&](const std::string& name, int master, double scale, double offset) {
      const int j = id(mjOBJ_JOINT, mjcf_joint_name(name));
      driven_.push_back({m_->jnt_qposadr[j], m_->jnt_dofadr[j], master, scale, offset});
    };
    for (int j = 0; j < model.num_joints(); ++j) add(model.joints[j].name, j, 1.0, 0.0);
    for (const MimicJoint& mimic : model.mimics)
      add(mimic.name, model.find_joint(mimic.master), mimic.multiplier, mimic.offset);
    num_joints_ = model.num_joints();
    const int free_joint = m_->body_jntadr[id(mjOBJ_BODY, free_body)];
    if (free_joint < 0 || m_->jnt_type[free_joint] != mjJNT_FREE) {
      throw InputError("MuJoCo plant model: no free joint on the base body");
    }
    free_body_ = id(mjOBJ_BODY, free_body);
    free_qadr_ = m_->jnt_qposadr[free_joint];
    free_dadr_ = m_->jnt_dofadr[free_joint];
    sensor_body_ = id(mjOBJ_BODY, mjcf_body_name(model.sensor_link()));
    force_adr_ = m_->sensor_adr[id(mjOBJ_SENSOR, "massid_ft_force")];
    torque_adr_ = m_->sensor_adr[id(mjOBJ_SENSOR, "massid_ft_torque")];
    if (m_->nv != 6 + num_driven()) {
      throw InputError(fmt::format(
          "MuJoCo plant model has {} degrees of freedom, expected {} (6 + {} joints + {} mimic "
          "joints)",
          m_->nv, 6 + num_driven(), model.num_joints(), model.mimics.size()));
    }
    for (const Driven& j : driven_)
      if (j.master < 0 || j.master >= num_joints_)
        throw InputError("MuJoCo plant model: a mimic joint without its master");
    // Joints at 0: a mimic joint at its offset.
    for (const Driven& j : driven_) d_->qpos[j.qadr] = j.offset;
    const auto nv = static_cast<std::size_t>(m_->nv);
    x_.assign(nv, 0.0);
    mx_.assign(nv, 0.0);
    qpos0_.assign(static_cast<std::size_t>(m_->nq), 0.0);
    qvel0_.assign(nv, 0.0);
    dvel_.assign(nv, 0.0);
    dacc_.assign(nv, 0.0);
    for (auto& v : stage_vel_) v.assign(nv, 0.0);
    for (auto& a : stage_acc_) a.assign(nv, 0.0);
    full_m_.assign(nv * nv, 0.0);
    m_bj_.setZero(6, num_driven());
    m_jj_.setZero(num_driven(), num_driven());
    joint_acc_.setZero(num_driven());
    joint_tau_.setZero(num_driven());
    q_cmd_ = Eigen::VectorXd::Zero(model.num_joints());
    qd_cmd_ = Eigen::VectorXd::Zero(model.num_joints());
    qdd_cmd_ = Eigen::VectorXd::Zero(model.num_joints());
    platform_p_cmd_ = position();
    platform_r_cmd_ = rotation();
  }

  int num_joints() const { return num_joints_; }
  int num_driven() const { return static_cast<int>(driven_.size()); }

  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd* qdd) {
    check_size(q, "joint command q");
    check_size(qd, "joint command qd");
    if (qdd != nullptr) check_size(*qdd, "joint command qdd");
    q_cmd_ = q;
    qd_cmd_ = qd;
    if (qdd != nullptr) {
      qdd_cmd_ = *qdd;
    } else {
      qdd_cmd_.setZero();
    }
    joint_cmd_time_ = d_->time;
    stage_ = Stage::Stale;
  }

  void set_joints(const Eigen::VectorXd& q, bool stop_everything) {
    check_size(q, "joint positions");
    for (const Driven& j : driven_) {
      d_->qpos[j.qadr] = j.scale * q[j.master] + j.offset;
      d_->qvel[j.dadr] = 0.0;
    }
    if (stop_everything) mju_zero(d_->qvel, m_->nv);
    q_cmd_ = q;
    qd_cmd_.setZero();
    qdd_cmd_.setZero();
    joint_cmd_time_ = d_->time;
    stage_ = Stage::Stale;
  }

  void set_platform_command(const Eigen::Isometry3d& pose, const Twist* twist,
                            const Twist* acceleration) {
    const Eigen::Vector3d p = pose.translation();
    const Eigen::Matrix3d r = pose.linear();
    if (twist != nullptr) {
      platform_twist_cmd_ = *twist;
    } else if (d_->time > platform_cmd_time_) {
      const double dt = d_->time - platform_cmd_time_;
      platform_twist_cmd_.head<3>() = (p - platform_p_cmd_) / dt;
      platform_twist_cmd_.tail<3>() = rotation_log(r * platform_r_cmd_.transpose()) / dt;
    }
    if (acceleration != nullptr) {
      platform_acc_cmd_ = *acceleration;
    } else {
      platform_acc_cmd_.setZero();
    }
    platform_p_cmd_ = p;
    platform_r_cmd_ = r;
    platform_cmd_time_ = d_->time;
    stage_ = Stage::Stale;
  }

  void advance(double dt) {
    const double end = d_->time + dt;
    while (d_->time < end - 0.5 * m_->opt.timestep) rk4_step();
  }

  Wrench measured_wrench() {
    ensure(Stage::Sensors);
    Wrench w;
    for (int k = 0; k < 3; ++k) {
      w[k] = -d_->sensordata[force_adr_ + k];
      w[3 + k] = -d_->sensordata[torque_adr_ + k];
    }
    return w;
  }

  Eigen::Isometry3d body_pose(int body) {
    ensure(Stage::Kinematics);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      t.translation()[r] = d_->xpos[3 * body + r];
      for (int c = 0; c < 3; ++c) t.linear()(r, c) = d_->xmat[9 * body + 3 * r + c];
    }
    return t;
  }
  // Twist of a body frame: [velocity of its origin; angular velocity], world.
  Twist body_twist(int body) {
    ensure(Stage::Forward);
    mjtNum v[6];
    mj_objectVelocity(m_.get(), d_.get(), mjOBJ_BODY, body, v, 0);
    Twist t;
    t << v[3], v[4], v[5], v[0], v[1], v[2];
    return t;
  }
  Eigen::Isometry3d base_pose() { return body_pose(free_body_); }
  Twist base_twist() { return body_twist(free_body_); }
  Eigen::Isometry3d sensor_pose() { return body_pose(sensor_body_); }
  Twist sensor_twist() { return body_twist(sensor_body_); }

  Eigen::VectorXd joint_positions() const {
    Eigen::VectorXd q(num_joints());
    for (int j = 0; j < num_joints(); ++j)
      q[j] = d_->qpos[driven_[static_cast<std::size_t>(j)].qadr];
    return q;
  }
  Eigen::VectorXd joint_velocities() const {
    Eigen::VectorXd v(num_joints());
    for (int j = 0; j < num_joints(); ++j)
      v[j] = d_->qvel[driven_[static_cast<std::size_t>(j)].dadr];
    return v;
  }
  double time() const { return d_->time; }

  // Momenta of the subtree of the base body (the whole system).
  Eigen::Vector3d linear_momentum() {
    ensure(Stage::Forward);
    mj_subtreeVel(m_.get(), d_.get());
    return m_->body_subtreemass[free_body_] * Eigen::Vector3d(d_->subtree_linvel + 3 * free_body_);
  }
  Eigen::Vector3d angular_momentum() {
    ensure(Stage::Forward);
    mj_subtreeVel(m_.get(), d_.get());
    return Eigen::Vector3d(d_->subtree_angmom + 3 * free_body_);
  }
  Eigen::Vector3d center_of_mass() {
    ensure(Stage::Forward);
    return Eigen::Vector3d(d_->subtree_com + 3 * free_body_);
  }
  double total_mass() const { return m_->body_subtreemass[free_body_]; }

 private:
  void check_size(const Eigen::VectorXd& v, const char* what) const {
    if (v.size() != num_joints() || !v.allFinite()) {
      throw InputError(
          fmt::format("{}: {} finite values expected, got {}", what, num_joints(), v.size()));
    }
  }

  Eigen::Vector3d position() const {
    return Eigen::Vector3d(d_->qpos[free_qadr_], d_->qpos[free_qadr_ + 1],
                           d_->qpos[free_qadr_ + 2]);
  }
  Eigen::Matrix3d rotation() const {
    return Eigen::Quaterniond(d_->qpos[free_qadr_ + 3], d_->qpos[free_qadr_ + 4],
                              d_->qpos[free_qadr_ + 5], d_->qpos[free_qadr_ + 6])
        .normalized()
        .toRotationMatrix();
  }

  // How much of mjData is up to date with the state and the commands.
  // Commands and steps make it Stale; readers ask for what they need.
  enum class Stage { Stale, Kinematics, Forward, Sensors };

  void ensure(Stage need) {
    if (stage_ >= need) return;
    if (need == Stage::Kinematics) {
      mj_kinematics(m_.get(), d_.get());
      stage_ = Stage::Kinematics;
      return;
    }
    if (stage_ < Stage::Forward) forward();
    if (need == Stage::Sensors) {
      mj_sensorAcc(m_.get(), d_.get());  // force/torque: cfrc_int from mj_rnePostConstraint
      stage_ = Stage::Sensors;
    }
  }

  // What mj_forward computes for this model (no contacts, constraints,
  // tendons, actuators or passive forces), with the servo forces in between:
  // kinematics, composite inertia M and its factor, bias forces, then
  // qacc = M^-1 (qfrc_applied - qfrc_bias). A third cheaper than mj_forward.
  void forward() {
    mjModel* m = m_.get();
    mjData* d = d_.get();
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_crb(m, d);
    mj_factorM(m, d);
    mj_comVel(m, d);
    mj_rne(m, d, 0, d->qfrc_bias);
    apply_controls();
    mju_sub(d->qfrc_smooth, d->qfrc_applied, d->qfrc_bias, m->nv);
    mj_solveM(m, d, d->qacc, d->qfrc_smooth, 1);
    stage_ = Stage::Forward;
  }

  // One classical RK4 step as MuJoCo's mj_RungeKutta does it (positions on the
  // manifold with mj_integratePos), the servo forces evaluated at each stage.
  void rk4_step() {
    ensure(Stage::Forward);
    mjModel* m = m_.get();
    mjData* d = d_.get();
    const int nq = m->nq, nv = m->nv;
    const double h = m->opt.timestep, t0 = d->time;
    static constexpr double kA[3] = {0.5, 0.5, 1.0};  // stage i uses kA[i-1] * stage i-1
    static constexpr double kB[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
    mju_copy(qpos0_.data(), d->qpos, nq);
    mju_copy(qvel0_.data(), d->qvel, nv);
    mju_copy(stage_vel_[0].data(), d->qvel, nv);
    mju_copy(stage_acc_[0].data(), d->qacc, nv);
    for (int i = 1; i < 4; ++i) {
      const double a = kA[i - 1] * h;
      const auto& v = stage_vel_[static_cast<std::size_t>(i - 1)];
      const auto& acc = stage_acc_[static_cast<std::size_t>(i - 1)];
      mju_copy(d->qpos, qpos0_.data(), nq);
      mj_integratePos(m, d->qpos, v.data(), a);
      for (int k = 0; k < nv; ++k)
        d->qvel[k] = qvel0_[static_cast<std::size_t>(k)] + a * acc[static_cast<std::size_t>(k)];
      d->time = t0 + a;
      forward();
      mju_copy(stage_vel_[static_cast<std::size_t>(i)].data(), d->qvel, nv);
      mju_copy(stage_acc_[static_cast<std::size_t>(i)].data(), d->qacc, nv);
    }
    mju_zero(dvel_.data(), nv);
    mju_zero(dacc_.data(), nv);
    for (int i = 0; i < 4; ++i) {
      mju_addToScl(dvel_.data(), stage_vel_[static_cast<std::size_t>(i)].data(), kB[i], nv);
      mju_addToScl(dacc_.data(), stage_acc_[static_cast<std::size_t>(i)].data(), kB[i], nv);
    }
    mju_copy(d->qpos, qpos0_.data(), nq);
    mj_integratePos(m, d->qpos, dvel_.data(), h);
    for (int k = 0; k < nv; ++k)
      d->qvel[k] = qvel0_[static_cast<std::size_t>(k)] + h * dacc_[static_cast<std::size_t>(k)];
    d->time = t0 + h;
    stage_ = Stage::Stale;
  }

  // Servo forces into qfrc_applied from the state; needs the position and
  // velocity stages (M, bias) of the current state. Both servos act in
  // continuous time (every Runge-Kutta stage).
  void apply_controls() {
    const double t = d_->time;
    const int nv = m_->nv;
    std::fill(x_.begin(), x_.end(), 0.0);
    if (platform_servo_) {
      // Free joint: linear dofs world frame (body origin), angular dofs body frame.
      // Target held to second order: p + v tau + a tau^2 / 2, likewise for the attitude.
      const double tp = t - platform_cmd_time_;
      const Eigen::Vector3d v_target =
          platform_twist_cmd_.head<3>() + platform_acc_cmd_.head<3>() * tp;
      const Eigen::Vector3d w_target =
          platform_twist_cmd_.tail<3>() + platform_acc_cmd_.tail<3>() * tp;
      const Eigen::Vector3d p_target =
          platform_p_cmd_ +
          (platform_twist_cmd_.head<3>() + 0.5 * platform_acc_cmd_.head<3>() * tp) * tp;
      const Eigen::Matrix3d r_target =
          rotation_exp((platform_twist_cmd_.tail<3>() + 0.5 * platform_acc_cmd_.tail<3>() * tp) *
                       tp) *
          platform_r_cmd_;
      const Eigen::Matrix3d r = rotation();
      const Eigen::Vector3d e_lin = p_target - position();
      const Eigen::Vector3d e_rot = rotation_log(r.transpose() * r_target);
      const Eigen::Vector3d v(d_->qvel + free_dadr_);
      const Eigen::Vector3d w(d_->qvel + free_dadr_ + 3);
      const Eigen::Vector3d ed_lin = v_target - v;
      const Eigen::Vector3d ed_rot = r.transpose() * w_target - w;
      const Eigen::Vector3d a_lin = platform_acc_cmd_.head<3>();
      const Eigen::Vector3d a_rot = r.transpose() * platform_acc_cmd_.tail<3>();
      for (int k = 0; k < 3; ++k) {
        x_[static_cast<std::size_t>(free_dadr_ + k)] =
            a_lin[k] + options_.platform_kp * e_lin[k] + options_.platform_kd * ed_lin[k];
        x_[static_cast<std::size_t>(free_dadr_ + 3 + k)] =
            a_rot[k] + options_.platform_kp * e_rot[k] + options_.platform_kd * ed_rot[k];
      }
      // F = M_pp x_p + bias_p: M times x with the joint entries still zero.
      mj_mulM(m_.get(), d_.get(), mx_.data(), x_.data());
      for (int k = 0; k < 6; ++k) {
        const int dof = free_dadr_ + k;
        d_->qfrc_applied[dof] = mx_[static_cast<std::size_t>(dof)] + d_->qfrc_bias[dof];
      }
    } else {
      for (int k = 0; k < 6; ++k) d_->qfrc_applied[free_dadr_ + k] = 0.0;
    }
    // Joints, computed torque: the joint accelerations are exactly
    // a = qdd_cmd + kp e + kd e' whatever the base does, the target held to
    // second order between commands. With the base's applied force
    // f_b fixed, the base accelerates by a_b = M_bb^-1 (f_b - bias_b - M_bj a),
    // and tau = M_jb a_b + M_jj a + bias_j.
    //
    // A mimic joint is driven the same way, its target its master's actual
    // state: a = s a_master + kp e + kd e' with e = s q_master + o - q. Its
    // error then obeys e'' + kd e' + kp e = 0: started on its master (the
    // constructor, set_joints), it stays there to rounding, and RK4, linear in
    // the stages, keeps that (a linear invariant of the servoed motion).
    const double tj = t - joint_cmd_time_;
    for (int j = 0; j < num_driven(); ++j) {
      const Driven& dj = driven_[static_cast<std::size_t>(j)];
      double e = 0.0, ed = 0.0, feed = 0.0;
      if (j < num_joints()) {
        e = q_cmd_[j] + (qd_cmd_[j] + 0.5 * qdd_cmd_[j] * tj) * tj - d_->qpos[dj.qadr];
        ed = qd_cmd_[j] + qdd_cmd_[j] * tj - d_->qvel[dj.dadr];
        feed = qdd_cmd_[j];
      } else {
        const Driven& master = driven_[static_cast<std::size_t>(dj.master)];
        e = dj.scale * d_->qpos[master.qadr] + dj.offset - d_->qpos[dj.qadr];
        ed = dj.scale * d_->qvel[master.dadr] - d_->qvel[dj.dadr];
        feed = dj.scale * joint_acc_[dj.master];  // masters come first
      }
      joint_acc_[j] = feed + options_.joint_kp * e + options_.joint_kd * ed;
    }
    mj_fullM(m_.get(), full_m_.data(), d_->qM);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        full(full_m_.data(), nv, nv);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) m_bb_(r, c) = full(free_dadr_ + r, free_dadr_ + c);
      for (int j = 0; j < num_driven(); ++j) m_bj_(r, j) = full(free_dadr_ + r, dadr(j));
      rhs_[r] = d_->qfrc_applied[free_dadr_ + r] - d_->qfrc_bias[free_dadr_ + r];
    }
    for (int a = 0; a < num_driven(); ++a)
      for (int b = 0; b < num_driven(); ++b) m_jj_(a, b) = full(dadr(a), dadr(b));
    rhs_.noalias() -= m_bj_ * joint_acc_;
    base_llt_.compute(m_bb_);
    const Eigen::Matrix<double, 6, 1> base_acc = base_llt_.solve(rhs_);
    joint_tau_.noalias() = m_bj_.transpose() * base_acc;
    joint_tau_.noalias() += m_jj_ * joint_acc_;
    for (int j = 0; j < num_driven(); ++j)
      d_->qfrc_applied[dadr(j)] = joint_tau_[j] + d_->qfrc_bias[dadr(j)];
  }

  int dadr(int j) const { return driven_[static_cast<std::size_t>(j)].dadr; }

  PlantOptions options_;
  bool platform_servo_;
  Stage stage_ = Stage::Stale;
  std::unique_ptr<mjModel, ModelDeleter> m_;
  std::unique_ptr<mjData, DataDeleter> d_;
  // A driven joint's qpos and dof addresses; it is at scale q[master] + offset
  // (an independent joint: its own index, 1, 0; a mimic joint: its master's).
  struct Driven {
    int qadr = -1, dadr = -1, master = -1;
    double scale = 1.0, offset = 0.0;
  };
  std::vector<Driven> driven_;  // Model::joints, then Model::mimics
  int num_joints_ = 0;
  int free_body_ = -1, free_qadr_ = -1, free_dadr_ = -1;
  int sensor_body_ = -1, force_adr_ = -1, torque_adr_ = -1;
  std::vector<mjtNum> x_, mx_;  // platform servo accelerations and M times them
  std::vector<mjtNum> full_m_;  // dense joint-space inertia, nv x nv row-major
  Eigen::Matrix<double, 6, 6> m_bb_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> m_bj_;
  Eigen::MatrixXd m_jj_;
  Eigen::Matrix<double, 6, 1> rhs_;
  Eigen::LLT<Eigen::Matrix<double, 6, 6>> base_llt_;
  Eigen::VectorXd joint_acc_, joint_tau_;            // computed-torque servo workspace
  std::vector<mjtNum> qpos0_, qvel0_, dvel_, dacc_;  // RK4 workspace
  std::array<std::vector<mjtNum>, 4> stage_vel_, stage_acc_;
  Eigen::VectorXd q_cmd_, qd_cmd_, qdd_cmd_;
  double joint_cmd_time_ = 0.0;
  Eigen::Vector3d platform_p_cmd_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d platform_r_cmd_ = Eigen::Matrix3d::Identity();
  Twist platform_twist_cmd_ = Twist::Zero();
  Twist platform_acc_cmd_ = Twist::Zero();
  double platform_cmd_time_ = 0.0;
};

// ---------------------------------------------------------------------------

PlatformPlant::PlatformPlant(const Model& model, const PlatformGeometry& geometry,
                             const PlantOptions& options) {
  check_options(model, options);
  std::ostringstream x;
  x << "<mujoco model=\"massid_platform_plant\">\n"
    << options_xml(options.timestep, options.gravity) << "  <worldbody>\n"
    << "    <body name=\"massid_platform\" " << pose_attributes(geometry.home) << ">\n"
    << "      <joint name=\"massid_platform_free\" type=\"free\"/>\n"
    << "      "
    << inertial(Eigen::Vector3d::Zero(), options.platform_mass, options.platform_inertia) << "\n"
    << robot_mjcf(model, options, options.platform_T_sensor, 6) << "    </body>\n"
    << "  </worldbody>\n"
    << mimic_equalities_mjcf(model, 2) << kSensorsXml << "</mujoco>\n";
  sim_ = std::make_unique<MujocoSimulation>(model, x.str(), "massid_platform", true, options);
}

PlatformPlant::~PlatformPlant() = default;
PlatformPlant::PlatformPlant(PlatformPlant&&) noexcept = default;
PlatformPlant& PlatformPlant::operator=(PlatformPlant&&) noexcept = default;

void PlatformPlant::set_platform_command(const Eigen::Isometry3d& base_T_platform) {
  sim_->set_platform_command(base_T_platform, nullptr, nullptr);
}
void PlatformPlant::set_platform_command(const Eigen::Isometry3d& base_T_platform,
                                         const Twist& twist) {
  sim_->set_platform_command(base_T_platform, &twist, nullptr);
}
void PlatformPlant::set_platform_command(const Eigen::Isometry3d& base_T_platform,
                                         const Twist& twist, const Twist& acceleration) {
  sim_->set_platform_command(base_T_platform, &twist, &acceleration);
}
void PlatformPlant::set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  sim_->set_joint_command(q, qd, nullptr);
}
void PlatformPlant::set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                      const Eigen::VectorXd& qdd) {
  sim_->set_joint_command(q, qd, &qdd);
}
void PlatformPlant::set_joints(const Eigen::VectorXd& q) { sim_->set_joints(q, false); }
void PlatformPlant::advance(double dt) { sim_->advance(dt); }
Wrench PlatformPlant::measured_wrench() const { return sim_->measured_wrench(); }
Eigen::Isometry3d PlatformPlant::platform_pose() const { return sim_->base_pose(); }
Twist PlatformPlant::platform_twist() const { return sim_->base_twist(); }
Eigen::Isometry3d PlatformPlant::sensor_pose() const { return sim_->sensor_pose(); }
Eigen::VectorXd PlatformPlant::joint_positions() const { return sim_->joint_positions(); }
Eigen::VectorXd PlatformPlant::joint_velocities() const { return sim_->joint_velocities(); }
double PlatformPlant::time() const { return sim_->time(); }

// ---------------------------------------------------------------------------

FreeFloatingReference::FreeFloatingReference(const Model& model,
                                             const SpacecraftParameters& spacecraft,
                                             const Eigen::Isometry3d& world_T_interface0,
                                             const PlantOptions& options) {
  check_options(model, options);
  validate(spacecraft);
  const Eigen::Isometry3d world_T_body = world_T_interface0 * spacecraft.body_T_interface.inverse();
  std::ostringstream x;
  x << "<mujoco model=\"massid_free_floating_reference\">\n"
    << options_xml(options.timestep, Eigen::Vector3d::Zero()) << "  <worldbody>\n"
    << "    <body name=\"massid_spacecraft\" " << pose_attributes(world_T_body) << ">\n"
    << "      <joint name=\"massid_spacecraft_free\" type=\"free\"/>\n"
    << "      " << inertial(Eigen::Vector3d::Zero(), spacecraft.mass, spacecraft.inertia) << "\n"
    << robot_mjcf(model, options, spacecraft.body_T_interface, 6) << "    </body>\n"
    << "  </worldbody>\n"
    << mimic_equalities_mjcf(model, 2) << kSensorsXml << "</mujoco>\n";
  sim_ = std::make_unique<MujocoSimulation>(model, x.str(), "massid_spacecraft", false, options);
}

FreeFloatingReference::~FreeFloatingReference() = default;
FreeFloatingReference::FreeFloatingReference(FreeFloatingReference&&) noexcept = default;
FreeFloatingReference& FreeFloatingReference::operator=(FreeFloatingReference&&) noexcept = default;

void FreeFloatingReference::set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  sim_->set_joint_command(q, qd, nullptr);
}
void FreeFloatingReference::set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& qdd) {
  sim_->set_joint_command(q, qd, &qdd);
}
void FreeFloatingReference::set_joints(const Eigen::VectorXd& q) { sim_->set_joints(q, true); }
void FreeFloatingReference::advance(double dt) { sim_->advance(dt); }
Eigen::Isometry3d FreeFloatingReference::interface_pose() const { return sim_->sensor_pose(); }
Wrench FreeFloatingReference::interface_wrench() const { return sim_->measured_wrench(); }
Twist FreeFloatingReference::interface_twist() const { return sim_->sensor_twist(); }
Eigen::VectorXd FreeFloatingReference::joint_positions() const { return sim_->joint_positions(); }
Eigen::VectorXd FreeFloatingReference::joint_velocities() const { return sim_->joint_velocities(); }
double FreeFloatingReference::time() const { return sim_->time(); }
Eigen::Vector3d FreeFloatingReference::linear_momentum() const { return sim_->linear_momentum(); }
Eigen::Vector3d FreeFloatingReference::angular_momentum() const { return sim_->angular_momentum(); }
Eigen::Vector3d FreeFloatingReference::center_of_mass() const { return sim_->center_of_mass(); }
double FreeFloatingReference::total_mass() const { return sim_->total_mass(); }

}  // namespace massid::emulator

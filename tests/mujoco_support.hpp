// Shared helpers of the MuJoCo cross-checks (test_mujoco.cpp,
// test_mujoco_motion.cpp): model ownership, temporary files, MJCF number
// formatting, and MuJoCo's own reading of a URDF.
#pragma once

#include <mujoco/mujoco.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <locale>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "massid/core/model.hpp"

namespace massid::mujoco_test {

namespace fs = std::filesystem;

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// A temporary directory removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    path_ = fs::temp_directory_path() / ("massid_mujoco_" + tag + "_" + std::to_string(::getpid()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

inline ModelPtr load_mujoco(const fs::path& path) {
  char error[1000] = "";
  ModelPtr m(mj_loadXML(path.string().c_str(), nullptr, error, sizeof(error)));
  if (!m) throw std::runtime_error("MuJoCo cannot load " + path.string() + ": " + error);
  return m;
}

// Full precision: 17 significant digits read back to the same double.
inline std::string num(double v) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s << std::setprecision(17) << v;
  return s.str();
}

inline std::string vec(const Eigen::Vector3d& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}

inline std::string quat(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

// The URDF text with a <mujoco> element that keeps every link as a body with
// its mass (MuJoCo fuses static bodies and drops the root's mass otherwise).
inline std::string urdf_for_mujoco(const std::string& urdf) {
  std::size_t pos = urdf.find("<robot");
  while (pos != std::string::npos && urdf[pos + 6] != ' ' && urdf[pos + 6] != '>' &&
         urdf[pos + 6] != '\n' && urdf[pos + 6] != '\t' && urdf[pos + 6] != '\r') {
    pos = urdf.find("<robot", pos + 1);
  }
  if (pos == std::string::npos) throw std::runtime_error("no <robot> element");
  const std::size_t end = urdf.find('>', pos);
  if (end == std::string::npos) throw std::runtime_error("unterminated <robot> element");
  return urdf.substr(0, end + 1) +
         "\n  <mujoco><compiler fusestatic=\"false\" discardvisual=\"true\" "
         "balanceinertia=\"true\"/></mujoco>" +
         urdf.substr(end + 1);
}

inline int id_of(const mjModel* m, int type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0) throw std::runtime_error("MuJoCo model has no object named " + name);
  return id;
}

// Copies the numbers of the URDF as MuJoCo imported it into `target` (the
// generated model), matching bodies and joints by name. Returns the largest
// change of a copied number (how far the two readings of the URDF differ).
// The inertias (principal moments and axes) are copied but not compared.
inline double copy_imported_numbers(const massid::Model& model, const mjModel* imported,
                                    mjModel* target) {
  double change = 0.0;
  const auto copy = [&change](mjtNum* dst, const mjtNum* src, int n) {
    for (int k = 0; k < n; ++k) {
      change = std::max(change, std::abs(dst[k] - src[k]));
      dst[k] = src[k];
    }
  };
  // q and -q are the same rotation.
  const auto copy_quat = [&change](mjtNum* dst, const mjtNum* src) {
    double plus = 0.0, minus = 0.0;
    for (int k = 0; k < 4; ++k) {
      plus = std::max(plus, std::abs(dst[k] - src[k]));
      minus = std::max(minus, std::abs(dst[k] + src[k]));
    }
    change = std::max(change, std::min(plus, minus));
    mju_copy(dst, src, 4);
  };
  if (imported->nbody != model.num_links() + 1) {
    throw std::runtime_error("MuJoCo imported " + std::to_string(imported->nbody - 1) +
                             " bodies, massid has " + std::to_string(model.num_links()) + " links");
  }
  if (imported->njnt != model.num_joints()) {
    throw std::runtime_error("MuJoCo imported " + std::to_string(imported->njnt) +
                             " joints, massid has " + std::to_string(model.num_joints()));
  }
  for (const massid::Link& link : model.links) {
    const int src = id_of(imported, mjOBJ_BODY, link.name);
    const int dst = id_of(target, mjOBJ_BODY, link.name);
    copy(target->body_pos + 3 * dst, imported->body_pos + 3 * src, 3);
    copy_quat(target->body_quat + 4 * dst, imported->body_quat + 4 * src);
    copy(target->body_ipos + 3 * dst, imported->body_ipos + 3 * src, 3);
    copy(target->body_mass + dst, imported->body_mass + src, 1);
    mju_copy(target->body_iquat + 4 * dst, imported->body_iquat + 4 * src, 4);
    mju_copy(target->body_inertia + 3 * dst, imported->body_inertia + 3 * src, 3);
  }
  for (const massid::Joint& joint : model.joints) {
    const int src = id_of(imported, mjOBJ_JOINT, joint.name);
    const int dst = id_of(target, mjOBJ_JOINT, joint.name);
    if (imported->jnt_type[src] != target->jnt_type[dst]) {
      throw std::runtime_error("joint " + joint.name + ": MuJoCo imported another type");
    }
    copy(target->jnt_pos + 3 * dst, imported->jnt_pos + 3 * src, 3);
    copy(target->jnt_axis + 3 * dst, imported->jnt_axis + 3 * src, 3);
    copy(target->qpos0 + target->jnt_qposadr[dst], imported->qpos0 + imported->jnt_qposadr[src], 1);
  }
  // Derived quantity used by mj_comPos.
  for (int b = 0; b < target->nbody; ++b) target->body_subtreemass[b] = target->body_mass[b];
  for (int b = target->nbody - 1; b > 0; --b) {
    target->body_subtreemass[target->body_parentid[b]] += target->body_subtreemass[b];
  }
  return change;
}

}  // namespace massid::mujoco_test

// URDF -> Model. tinyxml2 checks the XML first so that syntax errors carry a
// line number; urdfdom then builds the tree; its log is captured so that its
// complaints reach the user as one line instead of going to the console.
#include <console_bridge/console.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <locale>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/edit_distance.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace massid {
namespace {

// The first element (document order) in the xacro namespace: a name prefixed
// "xacro:" or by any prefix an element declares for xacro's URI
// (xmlns:P="http://www.ros.org/wiki/xacro"); null when none.
bool xacro_uri(std::string_view uri) {
  return uri.find("ros.org/wiki/xacro") != std::string_view::npos;
}

const tinyxml2::XMLElement* first_xacro_element(const tinyxml2::XMLNode& node,
                                                std::vector<std::string>& prefixes) {
  for (const tinyxml2::XMLElement* e = node.FirstChildElement(); e; e = e->NextSiblingElement()) {
    const size_t declared = prefixes.size();
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      const std::string_view n = a->Name();
      if (n.substr(0, 6) == "xmlns:" && xacro_uri(a->Value()))
        prefixes.emplace_back(std::string(n.substr(6)) + ":");
    }
    const std::string_view name = e->Name();
    for (const std::string& p : prefixes)
      if (name.substr(0, p.size()) == p) return e;
    if (const tinyxml2::XMLElement* inner = first_xacro_element(*e, prefixes)) return inner;
    prefixes.resize(declared);
  }
  return nullptr;
}

const tinyxml2::XMLElement* first_xacro_element(const tinyxml2::XMLDocument& doc) {
  std::vector<std::string> prefixes{"xacro:"};
  return first_xacro_element(doc, prefixes);
}

class CaptureLog : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_error.empty())
      first_error = text;
  }
  std::string first_error;
};

// The first <tag name="name"> element, null when not found.
const tinyxml2::XMLElement* find_element(const tinyxml2::XMLDocument& doc, const char* tag,
                                         const std::string& name) {
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) return nullptr;
  for (auto* e = robot->FirstChildElement(tag); e; e = e->NextSiblingElement(tag)) {
    const char* n = e->Attribute("name");
    if (n && name == n) return e;
  }
  return nullptr;
}

// Line of the first <tag name="name"> element, 0 when not found.
int element_line(const tinyxml2::XMLDocument& doc, const char* tag, const std::string& name) {
  const tinyxml2::XMLElement* e = find_element(doc, tag, name);
  return e ? e->GetLineNum() : 0;
}

// True when text is exactly `count` finite numbers separated by blanks.
bool finite_numbers(const char* text, int count) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  double v = 0.0;
  int n = 0;
  while (in >> v) {
    if (!std::isfinite(v)) return false;
    ++n;
  }
  return in.eof() && n == count;
}

// urdfdom logs a malformed <inertial> origin or mass and goes on with a zero
// mass; a measured link's mass must not be silently wrong, so check them here.
// (<inertia> does not matter to static wrenches and is not checked.)
void check_inertial(const tinyxml2::XMLDocument& doc, const std::string& source,
                    const std::string& link) {
  const tinyxml2::XMLElement* e = find_element(doc, "link", link);
  const tinyxml2::XMLElement* inertial = e ? e->FirstChildElement("inertial") : nullptr;
  if (!inertial) return;
  const tinyxml2::XMLElement* mass = inertial->FirstChildElement("mass");
  const char* value = mass ? mass->Attribute("value") : nullptr;
  if (!value)
    throw InputError(fmt::format("{}:{}: link '{}': <inertial> has no <mass value=\"...\"/>",
                                 source, inertial->GetLineNum(), link));
  if (!finite_numbers(value, 1))
    throw InputError(fmt::format("{}:{}: link '{}': mass value '{}' is not a number", source,
                                 mass->GetLineNum(), link, value));
  if (const tinyxml2::XMLElement* origin = inertial->FirstChildElement("origin")) {
    for (const char* attr : {"xyz", "rpy"}) {
      const char* text = origin->Attribute(attr);
      if (text && !finite_numbers(text, 3))
        throw InputError(
            fmt::format("{}:{}: link '{}': inertial origin {}='{}' is not three numbers", source,
                        origin->GetLineNum(), link, attr, text));
    }
  }
}

// urdfdom accepts a link that is the child of two joints (its subtree would be
// measured twice) and a joint whose child is its own ancestor (a loop cut off
// from the root: its links silently vanish from the model, and urdfdom leaks
// them through the cycle of shared pointers). A URDF is a tree: checked here,
// before urdfdom sees the file.
void check_tree(const tinyxml2::XMLDocument& doc, const std::string& source) {
  struct Edge {
    std::string parent, joint;
    int line;
  };
  std::map<std::string, Edge> parent_of;  // child link -> its joint
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  auto link_of = [](const tinyxml2::XMLElement* joint, const char* tag) -> const char* {
    const tinyxml2::XMLElement* e = joint->FirstChildElement(tag);
    return e ? e->Attribute("link") : nullptr;
  };
  for (auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const char* parent = link_of(j, "parent");
    const char* child = link_of(j, "child");
    if (!name || !parent || !child) continue;  // urdfdom names what is missing
    const auto [it, inserted] = parent_of.emplace(child, Edge{parent, name, j->GetLineNum()});
    if (!inserted)
      throw InputError(fmt::format(
          "{}:{}: link '{}' is the child of two joints, '{}' (line {}) and '{}'; a URDF is a tree",
          source, j->GetLineNum(), child, it->second.joint, it->second.line, name));
  }
  // Walk up from every link; meeting a link this same walk already passed is a loop.
  std::map<std::string, int> walk_of;  // link -> the walk that reached it first
  int walk = 0;
  for (const auto& entry : parent_of) {
    ++walk;
    std::string at = entry.first;
    while (true) {
      const auto [seen, fresh] = walk_of.emplace(at, walk);
      if (!fresh) {
        if (seen->second != walk) break;  // joins a path already checked
        const Edge& edge = parent_of.at(at);
        throw InputError(
            fmt::format("{}:{}: joint '{}' closes a loop: link '{}' is its own ancestor; a URDF "
                        "is a tree",
                        source, edge.line, edge.joint, at));
      }
      const auto up = parent_of.find(at);
      if (up == parent_of.end()) break;
      at = up->second.parent;
    }
  }
}

// Names reach JSON output (params files), which must be UTF-8: nlohmann's
// writer refuses what is not (type_error 316: malformed, overlong, a
// surrogate, beyond U+10FFFF, truncated).
void check_name(const tinyxml2::XMLDocument& doc, const std::string& source, const char* tag,
                const std::string& name) {
  try {
    nlohmann::json(name).dump();
    return;
  } catch (const nlohmann::json::type_error&) {
  }
  std::string shown;
  for (const char ch : name) {
    const auto b = static_cast<unsigned char>(ch);
    shown += b < 0x80 ? std::string(1, ch) : fmt::format("\\x{:02X}", b);
  }
  throw InputError(fmt::format("{}:{}: {} name '{}' is not UTF-8 text", source,
                               element_line(doc, tag, name), tag, shown));
}

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

JointType joint_type(const urdf::JointConstSharedPtr& j, const std::string& source, int line) {
  switch (j->type) {
    case urdf::Joint::FIXED:
      return JointType::Fixed;
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      return JointType::Revolute;
    case urdf::Joint::PRISMATIC:
      return JointType::Prismatic;
    case urdf::Joint::FLOATING:
      // A mobile base or a legged robot: the sensor is below the floating joint.
      throw InputError(
          fmt::format(
              "{}:{}: joint '{}' is floating: massid measures the links below a sensor, and a "
              "floating joint cannot be among them; take the sensor link below it (sensor link "
              "'{}')",
              source, line, j->name, j->child_link_name),
          {{Hint::Setting::SensorLink, j->child_link_name}});
    default:
      throw InputError(
          fmt::format("{}:{}: joint '{}' is of an unsupported type (planar or unknown); massid "
                      "supports revolute, continuous, prismatic and fixed joints",
                      source, line, j->name));
  }
}

// A link's joint or a step of the chain above the sensor link: `j`'s name
// checked, its origin, type and (movable) unit axis into `out`; its line.
template <class LinkOrStep>
int read_joint(LinkOrStep& out, const urdf::JointConstSharedPtr& j,
               const tinyxml2::XMLDocument& doc, const std::string& source) {
  const int line = element_line(doc, "joint", j->name);
  check_name(doc, source, "joint", j->name);
  out.joint = j->name;
  out.origin = to_isometry(j->parent_to_joint_origin_transform);
  out.type = joint_type(j, source, line);
  if (out.type == JointType::Fixed) return line;
  out.axis = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z);
  if (out.axis.norm() < 1e-12)
    throw InputError(fmt::format("{}:{}: joint '{}' has a zero axis", source, line, j->name));
  out.axis.normalize();
  return line;
}

Joint make_joint(const urdf::JointConstSharedPtr& j, JointType type, int link,
                 const std::string& source, int line) {
  Joint joint;
  joint.name = j->name;
  joint.type = type;
  joint.continuous = j->type == urdf::Joint::CONTINUOUS;
  if (j->limits && !joint.continuous && j->limits->lower > j->limits->upper)
    throw InputError(fmt::format(
        "{}:{}: joint '{}' has its limits swapped: lower {} > upper {}; write the smaller "
        "value as lower",
        source, line, j->name, j->limits->lower, j->limits->upper));
  // lower == upper (both 0 when <limit> gives neither): no range, unlimited.
  if (j->limits && !joint.continuous && j->limits->upper > j->limits->lower) {
    joint.limited = true;
    joint.lower = joint.urdf_lower = j->limits->lower;
    joint.upper = joint.urdf_upper = j->limits->upper;
  }
  if (j->limits && j->limits->velocity > 0) joint.velocity_limit = j->limits->velocity;
  joint.link = link;
  return joint;
}

// "'a', 'b' or 'c'": the (at most five) names closest to `name`.
std::string closest_names(const std::string& name, std::vector<std::string> names) {
  std::stable_sort(names.begin(), names.end(), [&](const std::string& x, const std::string& y) {
    return detail::edit_distance(name, x) < detail::edit_distance(name, y);
  });
  if (names.size() > 5) names.resize(5);
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("'" + names[i] + "'");
  return out;
}

// Mimic joints: a mimic link moves with its master (Link::joint_index,
// joint_scale, joint_offset), and the master's range narrows to what the
// mimic's own limits allow. Every problem at once: a master that is itself a
// mimic joint (chains and cycles), fixed, or not below the sensor link.
struct PendingMimic {
  int link;
  std::string joint, master;
  double multiplier, offset;
  int line;
  JointType type;
  bool limited;
  double lower, upper;
};

void resolve_mimics(Model& model, const std::vector<PendingMimic>& pending,
                    const urdf::ModelInterface& urdf, const std::string& source) {
  std::vector<std::string> problems;
  std::vector<std::string> ignored, ignored_masters;  // mimic limits no master position meets
  for (const PendingMimic& m : pending) {
    const int j = model.find_joint(m.master);
    if (j >= 0) continue;
    const urdf::JointConstSharedPtr master = urdf.getJoint(m.master);
    std::string why;
    if (!master)
      why = "which does not exist";
    else if (master->mimic)
      why = fmt::format("which is a mimic joint itself (of '{}')", master->mimic->joint_name);
    else if (master->type == urdf::Joint::FIXED)
      why = "which is fixed";
    else
      why = fmt::format("which is not below the sensor link '{}'", model.sensor_link());
    problems.push_back(
        fmt::format("line {}: '{}' mimics '{}', {}", m.line, m.joint, m.master, why));
  }
  if (!problems.empty()) {
    std::string list;
    for (const std::string& p : problems) list += "\n  " + p;
    throw InputError(fmt::format(
        "{}: {} mimic joint{} cannot follow {} master: a mimic joint must follow a movable, "
        "independent joint below the sensor link{}",
        source, problems.size(), problems.size() == 1 ? "" : "s",
        problems.size() == 1 ? "its" : "their", list));
  }
  for (const PendingMimic& m : pending) {
    const int j = model.find_joint(m.master);
    Link& link = model.links[m.link];
    link.joint_index = j;
    link.joint_scale = m.multiplier;
    link.joint_offset = m.offset;
    model.mimics.push_back({m.joint, m.master, m.multiplier, m.offset, m.link});
    Joint& master = model.joints[j];
    if (master.type != m.type)
      throw InputError(
          fmt::format("{}:{}: mimic joint '{}' is {} but its master '{}' is {}", source, m.line,
                      m.joint, m.type == JointType::Prismatic ? "prismatic" : "revolute", m.master,
                      master.type == JointType::Prismatic ? "prismatic" : "revolute"));
    if (!m.limited || m.multiplier == 0.0) continue;
    // q_mimic = a q + b in [lo, hi]  <=>  q in [(lo - b) / a, (hi - b) / a] (swapped for a < 0)
    double lo = (m.lower - m.offset) / m.multiplier, hi = (m.upper - m.offset) / m.multiplier;
    if (lo > hi) std::swap(lo, hi);
    if (master.limited) {
      lo = std::max(lo, master.lower);
      hi = std::min(hi, master.upper);
    }
    if (!(lo < hi)) {
      // Published grippers copy one <limit> to every finger, with multipliers
      // of -1: taken literally the master could not move. Keep its own range
      // (one note for all such joints: a gripper has several).
      ignored.push_back(fmt::format("'{}' (line {}: = {} x '{}' + {}, [{}, {}])", m.joint, m.line,
                                    m.multiplier, m.master, m.offset, m.lower, m.upper));
      ignored_masters.push_back(
          fmt::format("'{}' in [{}, {}]", m.master, master.lower, master.upper));
      continue;
    }
    master.limited = true;
    master.lower = lo;
    master.upper = hi;
  }
  if (!ignored.empty()) {
    std::sort(ignored_masters.begin(), ignored_masters.end());
    ignored_masters.erase(std::unique(ignored_masters.begin(), ignored_masters.end()),
                          ignored_masters.end());
    model.warnings.push_back(fmt::format(
        "{}: the limits of mimic joint{} {} are met by no position of their master ({}): they are "
        "ignored (the master keeps its own limits)",
        source, ignored.size() > 1 ? "s" : "", fmt::join(ignored, ", "),
        fmt::join(ignored_masters, ", ")));
  }
}

}  // namespace

Model load_urdf_string(const std::string& xml, const std::string& sensor_link,
                       const std::string& source) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS) {
    // ErrorStr() is "Error=NAME ErrorID=N (0xN) Line number=N[: detail]": keep name and detail.
    const std::string what = doc.ErrorStr() ? doc.ErrorStr() : "";
    const size_t detail = what.find(": ", what.find("Line number="));
    throw InputError(fmt::format("{}:{}: malformed XML: {}{}", source,
                                 std::max(1, doc.ErrorLineNum()), doc.ErrorName(),
                                 detail == std::string::npos ? "" : what.substr(detail)));
  }
  if (!doc.FirstChildElement("robot"))
    throw InputError(fmt::format("{}:1: not a URDF: no <robot> element", source));
  // An unexpanded xacro file: an element in the xacro namespace (expanded
  // files keep xmlns:xacro, not its elements; "xacro" in a comment, a name or
  // any other text is no xacro).
  if (const tinyxml2::XMLElement* e = first_xacro_element(doc))
    throw InputError(fmt::format(
        "{}:{}: this is a xacro file, not a URDF: expand it first (xacro {} > robot.urdf)", source,
        e->GetLineNum(), source));
  check_tree(doc, source);

  CaptureLog capture;
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr urdf;
  try {
    urdf = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    capture.first_error = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!urdf) {
    throw InputError(fmt::format(
        "{}: invalid URDF: {}", source,
        capture.first_error.empty() ? "urdfdom rejected the file" : capture.first_error));
  }

  const std::string sensor = sensor_link.empty() ? urdf->getRoot()->name : sensor_link;
  urdf::LinkConstSharedPtr root = urdf->getLink(sensor);
  if (!root) {
    std::vector<std::string> names;
    for (const auto& [name, link] : urdf->links_) names.push_back(name);
    throw InputError(fmt::format("{}: unknown sensor link '{}' ({} links; closest: {})", source,
                                 sensor, names.size(), closest_names(sensor, names)));
  }

  Model model;
  model.name = urdf->getName();
  model.source = source;
  model.root_link = urdf->getRoot()->name;
  // The chain above the sensor link, walked up and then reversed (root first).
  // A chain with a joint massid cannot model (mimic, floating, planar) is
  // dropped: the sensor frame's gravity must then come from gx,gy,gz columns.
  try {
    for (urdf::LinkConstSharedPtr at = root; at->parent_joint; at = at->getParent()) {
      ChainStep step;
      read_joint(step, at->parent_joint, doc, source);
      model.upstream.insert(model.upstream.begin(), step);
    }
    for (ChainStep& step : model.upstream) {
      const urdf::JointConstSharedPtr j = urdf->getJoint(step.joint);
      if (step.type == JointType::Fixed || j->mimic) continue;
      step.joint_index = model.num_upstream_joints();
      model.upstream_joints.push_back(
          make_joint(j, step.type, -1, source, element_line(doc, "joint", step.joint)));
    }
    // A mimic joint above the sensor follows a master in the same chain.
    for (ChainStep& step : model.upstream) {
      const urdf::JointConstSharedPtr j = urdf->getJoint(step.joint);
      if (step.type == JointType::Fixed || !j->mimic) continue;
      const auto& uj = model.upstream_joints;
      const auto it = std::find_if(uj.begin(), uj.end(),
                                   [&](const Joint& m) { return m.name == j->mimic->joint_name; });
      if (it == uj.end())
        throw InputError(
            fmt::format("{}: mimic joint '{}' above the sensor follows '{}', "
                        "which is not in the chain above the sensor",
                        source, j->name, j->mimic->joint_name));
      step.joint_index = static_cast<int>(it - uj.begin());
      step.joint_scale = j->mimic->multiplier;
      step.joint_offset = j->mimic->offset;
    }
  } catch (const InputError&) {
    model.upstream.clear();
    model.upstream_joints.clear();
  }

  // Depth-first from the sensor link; children in the order urdfdom keeps them.
  struct Pending {
    urdf::LinkConstSharedPtr link;
    int parent;
  };
  std::vector<Pending> stack{{root, -1}};
  std::vector<PendingMimic> mimics;
  while (!stack.empty()) {
    Pending cur = stack.back();
    stack.pop_back();
    check_name(doc, source, "link", cur.link->name);
    Link link;
    link.name = cur.link->name;
    link.parent = cur.parent;
    if (cur.link->inertial) {
      check_inertial(doc, source, cur.link->name);
      link.has_inertial = true;
      link.mass = cur.link->inertial->mass;
      const auto& p = cur.link->inertial->origin.position;
      link.com = Eigen::Vector3d(p.x, p.y, p.z);
      const urdf::Inertial& in = *cur.link->inertial;
      Eigen::Matrix3d inertia;
      inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Eigen::Matrix3d r = to_isometry(in.origin).linear();  // inertial frame -> link frame
      link.inertia = r * inertia * r.transpose();
      if (!(link.mass >= 0.0))
        throw InputError(fmt::format("{}:{}: link '{}' has a negative mass", source,
                                     element_line(doc, "link", link.name), link.name));
    }
    for (const auto& c : cur.link->collision_array) {
      if (!c || !c->geometry) continue;
      double radius = -1.0;
      switch (c->geometry->type) {
        case urdf::Geometry::SPHERE:
          radius = static_cast<const urdf::Sphere&>(*c->geometry).radius;
          break;
        case urdf::Geometry::BOX: {
          const urdf::Vector3& d = static_cast<const urdf::Box&>(*c->geometry).dim;
          radius = 0.5 * std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& cyl = static_cast<const urdf::Cylinder&>(*c->geometry);
          radius = std::hypot(cyl.radius, 0.5 * cyl.length);
          break;
        }
        default:
          ++link.collision_meshes;
      }
      const auto& p = c->origin.position;
      if (radius >= 0.0 && std::isfinite(radius))
        link.collision.push_back({Eigen::Vector3d(p.x, p.y, p.z), radius});
    }
    if (cur.parent >= 0) {
      const urdf::JointConstSharedPtr j = cur.link->parent_joint;
      const int line = read_joint(link, j, doc, source);
      if (link.type != JointType::Fixed) {
        const Joint joint = make_joint(j, link.type, model.num_links(), source, line);
        if (j->mimic) {
          mimics.push_back({model.num_links(), j->name, j->mimic->joint_name, j->mimic->multiplier,
                            j->mimic->offset, line, link.type, joint.limited, joint.lower,
                            joint.upper});
        } else {
          link.joint_index = model.num_joints();
          model.joints.push_back(joint);
        }
      }
    }
    const int index = model.num_links();
    model.links.push_back(link);
    // Push in reverse so the first child is visited first.
    for (auto it = cur.link->child_links.rbegin(); it != cur.link->child_links.rend(); ++it)
      stack.push_back({*it, index});
  }
  resolve_mimics(model, mimics, *urdf, source);
  return model;
}

Model load_urdf(const std::string& path, const std::string& sensor_link) {
  return load_urdf_string(read_file(path, "cannot open URDF file"), sensor_link, path);
}

}  // namespace massid

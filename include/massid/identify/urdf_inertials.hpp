// A URDF with some links' inertials replaced and every other byte kept: the
// identified URDF (`identify --urdf-out`). Comments, meshes, <mujoco> and
// <gazebo> blocks, attribute order, indentation and line endings stay as the
// author wrote them; only each edited link's <inertial> element is rewritten
// (or added, for a link that had none), in the URDF's convention:
//   <origin xyz="c" rpy="0 0 0"/>  centre of mass in the link frame
//   <mass value="m"/>
//   <inertia .../>                 about the centre of mass, link-frame axes
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/identify/physical.hpp"

namespace massid {

struct LinkInertial {
  std::string link;  // URDF link name
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // link frame, m
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about com, link frame, kg m^2
  std::string note;  // written as an XML comment inside the element ("" for none)
};

// `urdf` (the file's text; `source` names it in messages) with the inertials of
// `edits` written in. InputError when a link is not in the file, is named
// twice, or the text is not XML the edit can follow (it has been read by
// load_urdf first, so this means a construct the scanner does not know).
std::string replace_inertials(const std::string& urdf, const std::string& source,
                              const std::vector<LinkInertial>& edits);

// The identified URDF: the text of the model's URDF (Model::source) with the
// physically consistent inertials of every measured link written in (mass,
// centre of mass and inertia about it: physical.hpp; at rest the inertia about
// the centre of mass is the URDF's). A link the URDF gives no mass gets the
// fit's body, unless it is a frame fixed to a neighbour (PhysicalLink::unseen:
// ee_link, tool0, a massless root), whose body the fit gave the neighbour: it
// stays massless, and the URDF's root link without an <inertial> gets none;
// the file reproduces the fit's wrench exactly. `note` goes into each
// written element as a comment. InputError naming the file when it cannot be
// read.
std::string identified_urdf(const Model& model, const PhysicalSummary& physical,
                            const std::string& note);

}  // namespace massid

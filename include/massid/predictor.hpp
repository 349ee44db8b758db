// Real-time prediction of the gravity wrench from identified base parameters
// alone (never from the URDF's inertials):
//
//   f = M_t g + f_0,   m = H(q) x g + m_0,                      (paper eqs. 15, 29)
//   H(q) = sum_b (m_b p_b(q) + R_b(q) h_b)
//
// H is the first moment of the measured bodies in the sensor frame. Links joined
// by fixed joints are folded into one rigid body b; (m_b, h_b) are the base
// parameters mapped onto the bodies (the base parameters' representatives, all
// other standard parameters zero, which gives the same Y_b pi_b).
//
// Predictor is immutable and compiled once; PredictorData is the workspace.
// predict() does not allocate.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/model.hpp"

namespace massid {

using Wrench = Eigen::Matrix<double, 6, 1>;  // fx fy fz mx my mz

struct Predictor {
  struct Body {
    int parent = -1;                                         // body index, -1 for the sensor body
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // parent body -> joint frame
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // joint axis in the joint frame
    JointType type = JointType::Fixed;
    int joint = -1;                                          // index into q
    double mass = 0.0;                                       // m_b: moves with the body's origin
    Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();  // h_b, body frame
  };
  std::vector<Body> bodies;  // bodies[0] is the sensor body; parents come first
  double total_mass = 0.0;   // M_t
  Wrench offset = Wrench::Zero();
  int num_joints = 0;
};

// values: [num_unknowns] base parameters, then the six offsets when base.offset.
Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values);

// Workspace of predict(): sized once.
struct PredictorData {
  explicit PredictorData(const Predictor& predictor);
  std::vector<Eigen::Matrix3d> rotation;  // [num_bodies] R_b, body -> sensor frame
  std::vector<Eigen::Vector3d> position;  // [num_bodies] p_b, body origin in the sensor frame
};

// Gravity wrench at joint positions q [num_joints] and gravity g (sensor frame).
Wrench predict(const Predictor& predictor, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g);

}  // namespace massid

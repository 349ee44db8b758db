// Joint trajectories for the emulator in simulation: the arm's motion that the
// plant and the free-floating reference both follow. Each gives position,
// velocity and acceleration, so the joint servos can feed the acceleration
// forward (mujoco_plant.hpp explains why that matters).
#pragma once

#include <Eigen/Core>
#include <functional>

#include "massid/core/model.hpp"

namespace massid::emulator {

// Joint positions, velocities and accelerations at time t (Model::joints
// order), written into q, qd, qdd.
using JointTrajectory =
    std::function<void(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd)>;

// The built-in maneuver: starts and ends at rest; every joint swings from the
// middle of its range and back, q = mid + amplitude sin^2(pi t / duration), the
// amplitude 1.2 rad for revolute joints and a quarter of the range for
// prismatic ones, at most 0.45 of the range, all in the same sense.
JointTrajectory smooth_maneuver(const Model& model, double duration);

// Clamped cubic spline through (t_k, q.row(k)): twice continuously
// differentiable, at rest at both ends, held at the first row before t_0 and at
// the last after t_n. t must increase strictly; q has one column per joint.
JointTrajectory spline_trajectory(const Eigen::VectorXd& t, const Eigen::MatrixXd& q);

}  // namespace massid::emulator

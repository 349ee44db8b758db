// Rest windows of a continuous log: the static method (paper eqs. 32-36)
// needs the wrench of a mechanism at rest, while people record one log as the
// robot moves from pose to pose. The rows recorded while the joints (or the
// platform) move, and while the wrench still rings after a stop, are not
// static data: they are dropped, and each window of rest rows enters the fit.
//
// Every rest row is kept as a sample: for rows of one pose the least-squares
// estimate and its covariance are exactly those of the window's average
// weighted by its length (the within-window scatter does not depend on the
// parameters), while the outlier test still sees each row.
#pragma once

#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"

namespace massid {

enum class RestDetection {
  Auto,  // a log with t sampled at 10 Hz or faster whose joints, gravity or wrench move
  Off,   // every row is a sample (a plan-like log)
};

struct RestWindowOptions {
  RestDetection detection = RestDetection::Auto;
  double lag = 0.05;     // s: a row moves when it differs from the rows `lag` before and after
  double settle = 0.05;  // s dropped after each motion at least, and `lag` before
  // Trim each window further where its wrench has not settled (the ringing
  // after a stop, the sensor's own filter, the next move's start), as the
  // data show: see find_rest_windows.
  bool trim = true;
  double min_duration = 0.1;  // s: shorter windows are dropped
  double max_step = 0.1;      // s: a log sampled slower is a set of poses, not a continuous log
  // With the model (find_rest_windows(model, ...)): a continuous log whose
  // largest inertial force and moment stay below this share of the wrench's
  // noise throughout is quasi-static: every row is a sample. 0: never.
  double quasi_static = 0.25;
};

struct RestWindow {
  int first = 0, last = 0;  // rows [first, last] of the samples
};

struct RestWindows {
  bool continuous = false;          // motion was found: only the windows' rows are samples
  std::vector<RestWindow> windows;  // in row order (one over every row when !continuous)
  int rows = 0;                     // rows of the log
  int samples = 0;                  // rows inside the windows
  int moving = 0;                   // rows found moving (joints, gravity or wrench)
  std::string criterion;            // what showed the motion: "joints", "gravity", "wrench"
  int trimmed = 0;                  // rows the settling check cut from the windows
  double longest_settling = 0.0;    // s: the longest cut at a window's start
  // A continuous log found quasi-static (find_rest_windows with the model):
  // every row is a sample (continuous false, one window), and the numbers
  // that justify it. Also filled, quasi_static false, when the check ran and
  // found the motion too fast.
  bool quasi_static = false;
  bool inertia_checked = false;  // the check ran (the numbers below are set)
  double max_speed = 0.0;  // the joints' largest speed (above and below the sensor), rad/s or m/s
  double inertial_force =
      0.0;  // N: the largest inertial force the motion produces (URDF inertials)
  double inertial_moment = 0.0;  // N m: the same for the moment
  double noise_force = 0.0;      // N: the force noise (the smallest of fx, fy, fz)
  double noise_moment = 0.0;     // N m: the moment noise (the smallest of mx, my, mz)
  int windowed_samples = 0;      // rows the rest windows would have kept
};

// The rest windows of `samples` (rows in time order; needs time for Auto).
// Per signal (each joint, the gravity direction, the force) the tolerance is
// 8 times its noise, sigma = 1.4826 median|x[i+1] - x[i]| / sqrt(2), at least
// 1e-3 (rad, m, rad of gravity direction; the force: 1e-3 of its median
// magnitude). A row moves when some signal differs by more than its tolerance
// both from the row `lag` before and from the row `lag` after: rows between
// two poses, not the last or first row of a pose (a plan-like log whose
// poses change from one row to the next has no moving row). The log is
// continuous when joints or gravity moved, or, with gravity from the force,
// the force turned; the force then also marks the ringing after a stop. A
// force that jumps while nothing moves (a bump) leaves the log whole: the
// outlier test judges it.
// Settling (options.trim): the rest rows, `settle` after a motion and `lag`
// before one, may still carry what a motion leaves in the wrench (the
// structure ringing after a stop, the sensor's own low-pass filter catching
// up, the next move starting). Each window's level per wrench channel is the
// median of its second half; blocks of 20 ms (at least 2 rows) and of 8
// times that in the windows' second halves, pooled over the windows, give
// the noise of a block's mean deviation from the level and of its mean
// square deviation (robust scales). A window then starts after the last
// block of its first half whose mean is beyond 4.5 scales or whose mean
// square is beyond 6 (ringing, a lag's tail), and ends before the blocks at
// its end that are; `trimmed` counts the rows cut, and windows left shorter
// than min_duration are dropped.
RestWindows find_rest_windows(const Samples& samples, const RestWindowOptions& options = {});

// The same, and for a continuous log the check whether it is quasi-static:
// joints so slow throughout that the inertial wrench is far below the noise.
// The joints' velocities and accelerations (above the sensor link too) are
// central differences over `lag` of the positions and t; the inertial wrench
// at each row is the motion regressor's at them with gravity zero
// (regressor.hpp) times the URDF's inertials; the noise per channel is
// 1.4826 median|second difference| / sqrt(6) of the wrench (a slow trend
// cancels). When the largest inertial force and moment stay within
// options.quasi_static of the smallest force and moment noise, every row is a
// sample (quasi_static). Not for a log whose gravity turns without joints to
// explain it (a tilting platform's motion is not in the model) or comes from
// the force.
RestWindows find_rest_windows(const Model& model, const Samples& samples,
                              const RestWindowOptions& options = {});

// The samples inside the windows (all of them when !windows.continuous).
Samples rest_samples(const Samples& samples, const RestWindows& windows);

}  // namespace massid

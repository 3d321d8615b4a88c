// Sliding-window pose smoothing for a camera without wheels: the poses of the last few frames
// are optimised together over every registration link of those frames (each link a pose
// measurement T_odom_cur = T_odom_reference * T_reference_cur with its covariance) and a
// constant-velocity term between consecutive steps (a hand-held camera's inertia):
//
//   min  sum_links rho(|L_k Log(Z_k^-1 X_i)|^2) + sum_i |S (Log(X_i^-1 X_i+1) / dt_i+1
//                                                          - Log(X_i-1^-1 X_i) / dt_i) dt|^2
//
// L_k^T L_k is the link's information (registration covariance, scaled), rho a Cauchy loss on
// the whitened residual (robust_sigmas), S the inverse acceleration sigmas per frame (dt the
// mean frame interval). Each link is its own robust term: a link that followed a walker, or a
// reference keyframe placed during a bad stretch, is down-weighted against the others and the
// window's motion instead of being averaged in. The oldest pose of the window is held fixed
// (it was handed out long ago; gauge). Gauss-Newton with iteratively re-weighted links;
// numerical derivatives of the small residual blocks (a window of 20 poses solves in well
// under a millisecond).
#pragma once

#include <deque>
#include <vector>

#include "core/common/pose.h"
#include "core/common/time.h"

namespace icgm {

class OptionReader;

struct PoseWindowOptions {
  int frames = 0;  // poses optimised together; < 3: off
  // Change of the per-frame step between consecutive frames (the constant-velocity term).
  double acceleration_sigma_m = 0.003;
  double acceleration_sigma_deg = 0.3;
  // Cauchy scale of a link's whitened residual (in sigmas); <= 0: plain squares.
  double robust_sigmas = 3.0;
  // The same for the constant-velocity term (a jerk of the hand); <= 0: plain squares.
  double acceleration_robust_sigmas = 0.0;
  int iterations = 6;
};

// Reads the window_* keys of the `frontend:` section; throws LoadError on bad values.
void ReadOptions(const OptionReader& reader, PoseWindowOptions* options);

// One measurement of a frame's pose (T_odom_camera) with its covariance ((t, r) twist layout,
// right perturbation in the camera frame).
struct PoseLink {
  Pose3 odom_camera = Pose3::Identity();
  Mat6 covariance = Mat6::Identity();
};

class PoseWindow {
 public:
  // `max_gap_s`: a step longer than this restarts the window.
  PoseWindow(const PoseWindowOptions& options, double max_gap_s);

  // Appends a frame at `stamp` (after the newest) with its links and returns its optimised pose.
  // `initial` starts the optimisation; without links the frame keeps `initial` and is held
  // fixed (a pose from another source: the window's motion restarts from it).
  Pose3 Add(Time stamp, const std::vector<PoseLink>& links, const Pose3& initial);
  void Clear() { frames_.clear(); }
  size_t size() const { return frames_.size(); }
  // The optimised pose of the i-th frame of the window (0: oldest).
  const Pose3& pose(size_t i) const { return frames_[i].pose; }
  // Robust weight (0-1) of the newest frame's links after the last Add (1: fully trusted).
  const std::vector<double>& last_link_weights() const { return last_weights_; }

 private:
  struct Entry {
    Time stamp;
    Pose3 pose;
    std::vector<PoseLink> links;
    bool fixed = false;
  };
  void Optimise();

  PoseWindowOptions options_;
  double max_gap_s_;
  std::deque<Entry> frames_;
  std::vector<double> last_weights_;
};

}  // namespace icgm

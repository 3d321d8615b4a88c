// Figures of a monocular trajectory against ground truth: the Sim(3)-aligned ATE (the scale of
// a monocular map is arbitrary; trajectory_evaluation.h with estimate_scale) and that error in
// per cent of the distance travelled, the figure of thesis Table 6.5.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"

namespace icgm {

struct MonoEvaluation {
  TrajectoryEvaluation evaluation;  // Sim(3) alignment
  double distance_m = 0.0;          // ground-truth path length over the associated poses
  double error_percent = 0.0;       // 100 * ATE RMSE / distance_m
  double scale = 1.0;               // Sim(3) scale, metres per map unit
};

// Length of the polyline through the positions, in order.
double PathLengthM(const std::vector<Pose3>& poses);

// Sim(3) ATE of `estimate` against `groundtruth` (association within max_dt_s); fails like
// EvaluateTrajectory, or when the associated ground truth does not move.
Status EvaluateMonoTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt_s, MonoEvaluation* out);

// Relative error over segments of fixed length: the translational error of the KITTI odometry
// benchmark (Geiger et al., CVPR 2012), with the segment lengths taken as fractions of the
// ground truth's path as rpg_trajectory_evaluation does for short runs (Zhang and Scaramuzza,
// IROS 2018: 10, 20, 30, 40 and 50 %). For each length L and each associated pose i, j is the
// first associated pose whose ground-truth path from i is at least L long;
// E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) on the Sim(3)-aligned estimate (one scale for the run, so
// scale drift counts where it happens), and the segment's error is 100 |t(E)| / path(i..j).
// Unlike the whole-run ATE in % of the distance, an error (a heading jump, a scale jump at a
// reset) counts in the segments that span it and is not carried into the later ones.
struct MonoSegmentLength {
  double fraction = 0.0;  // of the ground truth's path length
  double length_m = 0.0;
  size_t segments = 0;
  double mean_percent = 0.0;
};

struct MonoSegmentErrors {
  std::vector<MonoSegmentLength> lengths;
  std::vector<double> errors_percent;  // every segment of every length, lengths in order
  double mean_percent = 0.0;           // over all segments of all lengths
  double median_percent = 0.0;
  // The mean an estimate with the true rotations and no translation would score (the truth's
  // straight-line displacement over its path length): a scale for the figures above.
  double standing_still_percent = 0.0;
  // What makes up the error, per segment, then averaged over all: the angle of E's rotation
  // (deg); the angle between the estimated and the true displacement in the first pose's frame
  // (deg; 90 is no agreement, the mean over segments where both move); the estimated over the
  // true displacement's length (median); and 100 ||t_est| - |t_true|| / path, the error with
  // the estimated displacement turned onto the true direction (only its length wrong).
  double rotation_error_deg = 0.0;
  double direction_error_deg = 0.0;
  double length_ratio_median = 0.0;
  double length_only_percent = 0.0;
};

// `aligned`: an EvaluateMonoTrajectory result. Fails when a fraction is not in (0, 1) or no
// segment fits.
Status EvaluateMonoSegments(const TrajectoryEvaluation& aligned,
                            const std::vector<double>& length_fractions, MonoSegmentErrors* out);

// The fractions of the path rpg_trajectory_evaluation uses: 0.1, 0.2, 0.3, 0.4, 0.5.
std::vector<double> DefaultSegmentFractions();

// One map of a run (a reset starts a new one) aligned on its own.
struct MonoMapFigures {
  bool aligned = false;  // at least 10 poses and a Sim(3) alignment
  size_t poses = 0;      // poses of the map (associated ones when aligned)
  double scale = 0.0;    // its Sim(3) scale, metres per map unit
  double ate_rmse_m = 0.0;
  double distance_m = 0.0;
  // Sim(3) scale of its first and of its last kEdgePoses poses alone (0: fewer poses or no
  // alignment): the local scale where a re-initialization starts it and where it is lost.
  double scale_first = 0.0;
  double scale_last = 0.0;
  static constexpr size_t kEdgePoses = 20;
};

// Where the error of a run with several maps comes from. All three are % of the distance:
//  - whole: one Sim(3) for the run (EvaluateMonoTrajectory);
//  - scale_fixed: one Sim(3) after every map's motion is rescaled to the first aligned map's
//    units with the ground truth's scales (each step between consecutive poses multiplied by
//    scale of its map / scale of the first), i.e. the error left if every re-initialization
//    had carried the scale exactly; whole - scale_fixed is the share of the scale jumps;
//  - carry_fixed: as scale_fixed, but each map's factor is the one before times the jump of
//    the local scale at the re-initialization (scale_first of the map over scale_last of the
//    one before): the error left if every re-initialization had carried the scale of the last
//    poses exactly, the drift of the scale inside the maps kept;
//  - per_map: every map its own Sim(3) (RMSE over all their poses / their summed distance):
//    what is left inside the maps once the jumps of scale, position and orientation between
//    them are gone.
// The error one re-initialization brings in where map k (k >= 1) follows map k - 1: the last
// kJoinPoses poses of the map before and the first of the new map (its reference frame first)
// are each aligned with the ground truth on their own (Sim(3) scale from the positions, the
// rotation from the orientations, which a short stretch of a turning camera fixes better than
// its positions do); with a seamless join both give the same similarity.
struct MonoJoinFigures {
  size_t map = 0;        // the new map's index
  bool aligned = false;  // both sides aligned (at least kMinPoses poses each)
  // Scale of the new map's first poses over that of the map before's last (1: carried exactly).
  double scale_ratio = 1.0;
  // Angle between the two alignments' rotations (deg): the orientation the join lost.
  double rotation_deg = 0.0;
  // Distance (m) between the new map's reference frame placed by either alignment: the
  // position the join lost (the motion over the frames without a pose among it).
  double position_m = 0.0;
  // Time from the map before's last pose to the new map's reference frame, and the ground
  // truth's motion over it (the motion a reference frame placed at the last pose misses).
  double gap_s = 0.0;
  double gap_motion_m = 0.0;
  double gap_rotation_deg = 0.0;
  static constexpr size_t kJoinPoses = 20;
  static constexpr size_t kMinPoses = 6;
};

struct MonoMapBreakdown {
  std::vector<MonoMapFigures> maps;
  std::vector<MonoJoinFigures> joins;  // one per map after the first
  // % of distance with every join made exact: each new map moved by the similarity that takes
  // its first poses' alignment onto the (already corrected) map before's last poses' one, so
  // only the error inside the maps is left (scale, rotation, position at the joins removed).
  double joins_fixed_percent = 0.0;
  // ... with the rotation and position of every join made exact and the scales left as they
  // are (each new map's first poses aligned at the scale of the map before's last ones).
  double joins_rigid_fixed_percent = 0.0;
  double whole_percent = 0.0;
  double scale_fixed_percent = 0.0;
  double carry_fixed_percent = 0.0;
  double per_map_percent = 0.0;
  size_t aligned_maps = 0;
};

// `maps`: the poses of each map in stamp order (a pose whose stamp repeats in a later map, a
// re-initialization's reference frame, is taken from the later one). Fails like
// EvaluateMonoTrajectory on the whole run or when no map aligns on its own.
Status BreakDownMonoMaps(const Trajectory& groundtruth, const std::vector<Trajectory>& maps,
                         double max_dt_s, MonoMapBreakdown* out);

// The map's own scale at one tracked frame, in metres per map unit: the median over the tracked
// points of the depth image's value at the point's pixel (`depth_m`, CV_32FC1 metres, NaN or 0
// invalid; the nearest pixel) over the point's depth in the camera in map units
// (`map_depths`, MonoFrameResult::tracked_depths). Independent of how well the camera's motion is
// estimated: a change over a map is a change of the map's scale. nullopt with fewer than 10
// points with a valid depth.
std::optional<double> MapScaleFromDepth(const cv::Mat& depth_m,
                                        const std::vector<Eigen::Vector2d>& pixels,
                                        const std::vector<double>& map_depths);

}  // namespace icgm

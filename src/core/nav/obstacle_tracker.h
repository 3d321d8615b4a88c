// Walkers' motion from depth: the obstacle cells the camera sees in one frame
// (ObstacleGrid::fresh_obstacles_m) are grouped into clusters (cells within link_distance_m of
// each other), clusters small enough to be a person are associated with the tracks of earlier
// frames (nearest predicted position within gate_m), and each track's velocity is the
// least-squares slope of its positions over the last history_s. A track not seen for
// track_timeout_s is dropped; until then it moves on with its velocity (a walker that left the
// camera's view is still predicted). Larger clusters (walls, tables) are not tracked.
//
// Prediction: a moving track (at least min_observations, speed >= moving_speed_mps) is a disc
// of its radius moving with constant velocity; PredictedClearance gives the distance from a
// point to the nearest such disc t seconds after the last update (the time-aware clearance of
// the guard and the local planner).
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/common/time.h"
#include "core/nav/obstacle_grid.h"

namespace icgm {

struct ObstacleTrackerOptions {
  double link_distance_m = 0.12;      // cells this close belong to one cluster
  double max_cluster_radius_m = 0.5;  // larger clusters are scenery, not tracked
  double min_radius_m = 0.25;         // a tracked body is at least this wide (half a shoulder)
  double gate_m = 0.6;                // association: cluster within this of a track's prediction
  double history_s = 0.8;             // velocity: slope of the positions over this long
  double track_timeout_s = 3.0;       // unseen for longer: dropped
  int min_observations = 3;           // before a track may count as moving
  double moving_speed_mps = 0.3;      // slower tracks are treated as standing (the grid has them)
  double max_speed_mps = 2.5;         // velocity estimates are clamped to this
  // Unseen standing walkers held: a track slower than moving_speed_mps when it goes out of view
  // (a walker waiting beside the robot, out of the forward camera's view) is held where it was
  // last seen (its slow velocity set to zero, no extrapolation) and kept this long instead of
  // track_timeout_s. Moving tracks still move on and time out as before. 0: off.
  double standing_hold_s = 0.0;
  // Only a track seen in at least this many frames is held (1: every track, even one seen in a
  // single frame); a younger track that goes out of view moves on and times out as without the
  // hold.
  int standing_hold_min_frames = 1;
  // Walker bodies (0: off): the cells the camera sees of a person are the front of the body, so
  // their centroid lies in front of the body's centre. A track's body (BodyDisc) is a
  // disc of at least body_radius_m whose centre lies body_offset_m behind the centroid, away
  // from the camera along the ray it was last seen on (Update's viewpoint).
  double body_offset_m = 0.0;
  double body_radius_m = 0.35;
  // Walker identity kept (0: off): a walker track (it moved once) that is lost - dropped after
  // its timeout, or coasting unseen on a prediction the walker no longer follows (it stopped or
  // turned out of view) - is remembered for reidentify_s after it was last seen. A cluster that
  // joins no track's prediction continues the nearest such walker when it lies within
  // reidentify_gate_m of the way that walker could have gone since (the segment from where it
  // was last seen to where its velocity predicts it now): same id, was_moving kept, the velocity
  // refitted from the new sightings only. Without it a found-again walker starts a new track
  // that counts as a walker only once it moves again.
  double reidentify_s = 0.0;
  double reidentify_gate_m = 0.5;
  // Robust velocity: each axis's slope is the median of the slopes between every pair of
  // positions in the history (Theil-Sen) instead of the least-squares slope, so that a few
  // positions of another cluster (a neighbour associated for a frame or two, two people
  // merged) do not set a standing walker moving. false: least squares (on: 8/10 goals on both
  // crowd seed sets of the benchmark, against 10/10 and 9/10).
  bool robust_velocity = false;
  // Memory of walkers that left the view to the side (0: off): a track not seen in an update
  // whose predicted disc is not wholly inside the camera's view (CameraView, given to Update),
  // so that the camera can neither confirm nor clear it, is remembered: kept up to
  // side_memory_s after it was last seen (instead of track_timeout_s), no longer counted as
  // moving (the walker rules on moving tracks leave it alone; CrowdGuardOptions::remembered_gap_m
  // keeps the robot's own motion off it), predicted with its velocity damped (it moves on
  // p + v tau (1 - exp(-age / tau)), tau = side_memory_damping_s: at most v tau in all) and its
  // disc growing by side_memory_growth_mps of age. A remembered track whose disc is wholly back
  // in view and not seen is dropped (the camera sees its place free); seen again, it is an
  // ordinary track again.
  double side_memory_s = 0.0;
  double side_memory_damping_s = 0.5;
  double side_memory_growth_mps = 0.1;
  // A remembered track keeps what it was for the other walker rules: moving or not, predicted
  // at its full velocity (Predict); the damped, growing disc is RememberedDisc's only.
  bool side_memory_keeps_moving = false;
};

// The camera's horizontal view on the floor (map frame): from the viewpoint, within
// half_fov_rad of the optical axis's direction yaw_rad, up to range_m.
struct CameraView {
  Eigen::Vector2d viewpoint_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  double half_fov_rad = 0.0;
  double range_m = 0.0;
  // The whole disc lies inside the view (a disc around the viewpoint: never).
  bool Contains(const Eigen::Vector2d& centre_m, double radius_m) const;
};

struct TrackedObstacle {
  int id = 0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // at last_seen (map frame)
  Eigen::Vector2d velocity_mps = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
  Time last_seen;
  int observations = 0;
  bool moving = false;
  bool was_moving = false;  // moving in some frame so far (a walker, not furniture)
  bool held = false;  // out of view and held in place (ObstacleTrackerOptions::standing_hold_s)
  // Not seen since its disc left the camera's view (ObstacleTrackerOptions::side_memory_s).
  bool remembered = false;
  // From position_m to the body's centre (ObstacleTrackerOptions::body_offset_m; zero when off
  // or seen without a viewpoint).
  Eigen::Vector2d body_offset_m = Eigen::Vector2d::Zero();
};

class ObstacleTracker {
 public:
  explicit ObstacleTracker(ObstacleTrackerOptions options = ObstacleTrackerOptions());

  // One frame's obstacle cells (map frame), seen at `stamp` (strictly increasing) from
  // `viewpoint_m` (the camera on the floor, map frame; for the walkers' bodies) with `view`
  // (for the side memory; without it no track is remembered).
  void Update(Time stamp, const std::vector<Eigen::Vector2d>& cells_m,
              const std::optional<Eigen::Vector2d>& viewpoint_m = std::nullopt,
              const std::optional<CameraView>& view = std::nullopt);
  void Clear();

  const std::vector<TrackedObstacle>& tracks() const { return tracks_; }
  // Tracks that move (see the header comment).
  std::vector<TrackedObstacle> MovingTracks() const;
  // Position of a track t_s seconds after the last update (a remembered track: its velocity
  // damped, unless side_memory_keeps_moving).
  Eigen::Vector2d Predict(const TrackedObstacle& track, double t_s) const;
  // A remembered track's disc t_s seconds after the last update: at its damped prediction, its
  // radius grown with its age (ObstacleTrackerOptions::side_memory_s).
  Disc RememberedDisc(const TrackedObstacle& track, double t_s) const;
  // Distance from p to the nearest moving track's disc t_s seconds after the last update
  // (negative inside one); +infinity without moving tracks.
  double PredictedClearance(const Eigen::Vector2d& p, double t_s) const;
  // The same for the standing walkers: tracks that moved once and are slower than
  // moving_speed_mps now (a walker waiting, or sliding past the robot), each a disc of its
  // radius where it was last seen, moving on with its slow velocity (held: in place);
  // +infinity without one. `unseen_only`: only those out of view in the last update.
  double StandingWalkerClearance(const Eigen::Vector2d& p, double t_s,
                                 bool unseen_only = false) const;
  // A track's body (ObstacleTrackerOptions::body_offset_m): the disc at least body_radius_m
  // wide around its body centre, t_s seconds after the last update at its estimated velocity
  // (the caller picks the tracks: walkers only, or every track).
  Disc BodyDisc(const TrackedObstacle& track, double t_s) const;
  // A track the walker rules consider: it moves, or moved once (a walker that stopped).
  static bool IsWalker(const TrackedObstacle& t) { return t.moving || t.was_moving; }
  // Not seen in the last update (out of view or hidden), not yet dropped.
  bool Unseen(const TrackedObstacle& track) const { return track.last_seen < now_; }
  // The discs the moving tracks sweep over the next horizon_s: each track's disc every step_s
  // from the last update on (t = 0 and t = horizon_s included).
  std::vector<Disc> SweptDiscs(double horizon_s, double step_s) const;
  Time last_update() const { return now_; }
  // Lost walkers found again so far (ObstacleTrackerOptions::reidentify_s).
  int reidentified() const { return reidentified_; }
  const ObstacleTrackerOptions& options() const { return options_; }

 private:
  struct Cluster {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double radius_m = 0.0;
  };
  struct History {
    std::deque<std::pair<double, Eigen::Vector2d>> samples;  // (time s, position)
  };
  std::vector<Cluster> ClusterCells(const std::vector<Eigen::Vector2d>& cells_m) const;
  void FitVelocity(const History& history, TrackedObstacle* track) const;
  // A remembered track's position t_s seconds after the last update, its velocity damped.
  Eigen::Vector2d DampedPosition(const TrackedObstacle& track, double t_s) const;

  ObstacleTrackerOptions options_;
  std::vector<TrackedObstacle> tracks_;
  std::vector<History> histories_;  // parallel to tracks_
  std::vector<TrackedObstacle> lost_;  // dropped walkers remembered (reidentify_s)
  int reidentified_ = 0;
  Time now_;
  bool started_ = false;
  int next_id_ = 1;
};

}  // namespace icgm

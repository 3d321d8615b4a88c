// Obstacles around the robot from the RGB-D camera's depth (people included: whatever stands
// on the floor is an obstacle). Each depth image is back-projected, moved into base_link, cut to
// the obstacle height band with PCL's PassThrough (the floor and the ceiling removed), thinned
// with a VoxelGrid and projected into a 2-D grid fixed in the navigation frame (map) and centred
// on the robot; the window rolls with the robot.
//
// Memory: a cell keeps its obstacle while out of view for at most memory_s; a cell in view whose
// depth reaches beyond it (or has no depth: nothing within range) is cleared at once (a walker
// that moved on). Cells never
// seen are unknown. Queries see obstacles inflated by the robot's radius plus the clearance.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/planar_scan.h"
#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/map/occupancy_grid.h"

namespace icgm {

struct ObstacleGridOptions {
  double resolution_m = 0.05;
  double size_m = 8.0;  // side of the square window centred on the robot
  // Height band above the floor (base_link z) whose points are obstacles.
  double min_height_m = 0.05;
  double max_height_m = 1.8;
  double max_range_m = 5.0;     // depth beyond this is ignored
  double voxel_size_m = 0.04;   // VoxelGrid leaf
  int pixel_step = 4;           // every n-th pixel of every n-th row is back-projected
  int min_points_per_cell = 2;  // voxels needed to mark a cell
  double memory_s = 3.0;        // an obstacle out of view is forgotten after this
  double robot_radius_m = 0.25;  // circular footprint
  double clearance_m = 0.30;     // kept beyond the footprint: inflation = radius + clearance
};

// A disc on the floor (map frame): a walker's body at some instant.
struct Disc {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
};

class ObstacleGrid {
 public:
  explicit ObstacleGrid(ObstacleGridOptions options = ObstacleGridOptions());

  // One depth image (CV_32FC1 metres, NaN or 0 invalid) seen by the camera at T_map_base *
  // T_base_camera. Re-centres the window on the robot, ages the memory, clears cells seen free
  // and marks the new obstacles. Fails (grid unchanged) on an empty or mistyped image.
  Status AddDepth(Time stamp, const cv::Mat& depth_m, const CameraIntrinsics& intrinsics,
                  const Pose3& T_base_camera, const Pose3& T_map_base);
  // A planar range scan taken with the robot at T_map_base, the scanner mounted at
  // T_base_scanner; the same grid, memory and fresh cells as depth. Each return inside the
  // height band marks its cell (one return suffices: a scan has no stray points); the cells
  // along each beam up to 0.15 m before its return (or to range_max_m when it returned
  // nothing) are seen free, and an obstacle a scan marked there is cleared (not one from depth:
  // the plane may pass over a table the camera saw), except cells marked at this stamp. With
  // `same_frame` the scan belongs to the last update (e.g. the depth image of the same
  // instant): its cells are added to fresh_obstacles_m() instead of replacing them.
  void AddScan(const PlanarScan& scan, const Pose3& T_base_scanner, const Pose3& T_map_base,
               bool same_frame);
  // The centres (map frame) of the window's cells holding the scan's returns inside the height
  // band, each once, as AddScan would mark them; the grid is unchanged.
  std::vector<Eigen::Vector2d> ScanCells(const PlanarScan& scan, const Pose3& T_base_scanner,
                                         const Pose3& T_map_base) const;
  // Obstacle points given directly in the map frame (z is ignored), seen at `stamp`; re-centres
  // the window on `robot_xy_m` first. For callers with another obstacle source and for tests.
  void AddPoints(Time stamp, const Eigen::Vector2d& robot_xy_m,
                 const std::vector<Eigen::Vector2d>& points_m);
  void Clear();
  // A copy with the cells whose centres lie within the discs marked as obstacles seen now (in
  // the window only): e.g. the area walkers will sweep, for a planner that should keep out of
  // it. This grid is unchanged.
  ObstacleGrid WithDiscs(const std::vector<Disc>& discs) const;
  // The centres (map frame) of the live obstacle cells whose centres lie within `area`.
  std::vector<Eigen::Vector2d> ObstacleCells(const Disc& area) const;
  // Clears the obstacles of the cells holding these points (map frame; outside the window:
  // ignored), as if never hit: e.g. a walker's trail once it is seen elsewhere.
  void Forget(const std::vector<Eigen::Vector2d>& points_m);
  // A copy without the obstacles of the cells holding these points; this grid is unchanged.
  ObstacleGrid Without(const std::vector<Eigen::Vector2d>& points_m) const;

  // A raw obstacle in the cell holding (x, y) (outside the window: false).
  bool Obstacle(double x_m, double y_m) const;
  // Within the inflation (robot radius + clearance) of an obstacle: the robot's centre must
  // not be here.
  bool Occupied(double x_m, double y_m) const { return Clearance(x_m, y_m) < inflation_m(); }
  // Distance from (x, y) to the nearest obstacle cell's edge (m); max_clearance_m() when none is
  // within that distance or the point is outside the window.
  double Clearance(double x_m, double y_m) const;
  double max_clearance_m() const { return max_clearance_m_; }
  double inflation_m() const { return options_.robot_radius_m + options_.clearance_m; }

  // The grid as nav_msgs/OccupancyGrid carries it, in the map's grid type (row-major from the
  // origin, the lower-left corner of cell (0, 0)): -1 unknown, 0 free, 100 obstacle, 99 inside
  // the inflation (the robot's centre must not go there).
  OccupancyGrid Export() const;
  int ObstacleCount() const;
  // Centres (map frame) of the cells marked by the last AddDepth / AddPoints: what the sensor
  // sees now, without the memory (the input of ObstacleTracker).
  const std::vector<Eigen::Vector2d>& fresh_obstacles_m() const { return fresh_; }
  const ObstacleGridOptions& options() const { return options_; }

 private:
  struct Cell {
    double last_hit_s = -1e300;   // last time an obstacle point fell in it
    double last_seen_s = -1e300;  // last time it was observed (hit or seen free)
    float height_m = 0.0f;        // mean height of its obstacle points
    // The last mark came from a planar scan: a scan clears only such cells (its plane may pass
    // above or below what the depth saw there, e.g. over a table).
    bool from_scan = false;
  };
  // Moves the window so that it is centred on (x, y), keeping the overlap.
  void Recentre(const Eigen::Vector2d& xy_m);
  bool CellOf(double x_m, double y_m, int* col, int* row) const;
  Eigen::Vector2d CellCentre(int col, int row) const;  // in the map frame
  bool Alive(const Cell& cell) const;  // obstacle seen within memory_s of the last update
  // A copy owning its distance map (cv::Mat copies share their pixels).
  ObstacleGrid DeepCopy() const;
  // Calls visit(index into grid_, centre) for every window cell whose centre lies within `d`.
  template <typename Visit>
  void ForEachCellIn(const Disc& d, Visit visit) const;
  void UpdateDistance();

  ObstacleGridOptions options_;
  int cells_ = 0;          // window side in cells
  long origin_col_ = 0;    // global index of the window's cell (0, 0)
  long origin_row_ = 0;
  bool centred_ = false;
  double now_s_ = 0.0;  // stamp of the last update
  std::vector<Cell> grid_;
  std::vector<Eigen::Vector2d> fresh_;
  cv::Mat distance_m_;  // CV_32F distance of each cell to the nearest obstacle (m)
  double max_clearance_m_ = 2.0;
};

}  // namespace icgm

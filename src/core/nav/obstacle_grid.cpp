#include "core/nav/obstacle_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>
#include <pcl/filters/passthrough.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace icgm {
namespace {

constexpr double kNever = -1e300;
// A cell counts as seen free when the depth reaches this much beyond it.
constexpr double kSeeThroughMarginM = 0.15;

}  // namespace

ObstacleGrid::ObstacleGrid(ObstacleGridOptions options) : options_(options) {
  cells_ = std::max(3, static_cast<int>(std::lround(options_.size_m / options_.resolution_m)));
  grid_.assign(static_cast<size_t>(cells_) * cells_, Cell());
  distance_m_ = cv::Mat(cells_, cells_, CV_32F, cv::Scalar(0));
  max_clearance_m_ = 0.5 * cells_ * options_.resolution_m;
  distance_m_.setTo(max_clearance_m_);
}

void ObstacleGrid::Clear() {
  std::fill(grid_.begin(), grid_.end(), Cell());
  fresh_.clear();
  distance_m_.setTo(max_clearance_m_);
  centred_ = false;
}

void ObstacleGrid::Recentre(const Eigen::Vector2d& xy_m) {
  const long col0 = static_cast<long>(std::floor(xy_m.x() / options_.resolution_m)) - cells_ / 2;
  const long row0 = static_cast<long>(std::floor(xy_m.y() / options_.resolution_m)) - cells_ / 2;
  if (centred_ && col0 == origin_col_ && row0 == origin_row_) return;
  std::vector<Cell> moved(grid_.size(), Cell());
  if (centred_) {
    for (int r = 0; r < cells_; ++r) {
      const long old_r = r + row0 - origin_row_;
      if (old_r < 0 || old_r >= cells_) continue;
      for (int c = 0; c < cells_; ++c) {
        const long old_c = c + col0 - origin_col_;
        if (old_c < 0 || old_c >= cells_) continue;
        moved[static_cast<size_t>(r) * cells_ + c] = grid_[old_r * cells_ + old_c];
      }
    }
  }
  grid_.swap(moved);
  origin_col_ = col0;
  origin_row_ = row0;
  centred_ = true;
}

bool ObstacleGrid::CellOf(double x_m, double y_m, int* col, int* row) const {
  if (!centred_) return false;
  const long c = static_cast<long>(std::floor(x_m / options_.resolution_m)) - origin_col_;
  const long r = static_cast<long>(std::floor(y_m / options_.resolution_m)) - origin_row_;
  if (c < 0 || r < 0 || c >= cells_ || r >= cells_) return false;
  *col = static_cast<int>(c);
  *row = static_cast<int>(r);
  return true;
}

Eigen::Vector2d ObstacleGrid::CellCentre(int col, int row) const {
  return Eigen::Vector2d((origin_col_ + col + 0.5) * options_.resolution_m,
                         (origin_row_ + row + 0.5) * options_.resolution_m);
}

Status ObstacleGrid::AddDepth(Time stamp, const cv::Mat& depth_m,
                              const CameraIntrinsics& intrinsics, const Pose3& T_base_camera,
                              const Pose3& T_map_base) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1) {
    return Status::Error("obstacle grid: depth must be a non-empty CV_32FC1 image in metres");
  }
  const double now = stamp.seconds();
  now_s_ = now;
  Recentre(T_map_base.translation().head<2>());

  // Depth -> base_link points (PCL), height band, voxel thinning.
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  const int step = std::max(1, options_.pixel_step);
  const Eigen::Matrix3f R = T_base_camera.linear().cast<float>();
  const Eigen::Vector3f t = T_base_camera.translation().cast<float>();
  cloud->reserve(static_cast<size_t>(depth_m.rows / step + 1) * (depth_m.cols / step + 1));
  for (int v = 0; v < depth_m.rows; v += step) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; u += step) {
      const float z = row[u];
      if (!std::isfinite(z) || z <= 0.0f || z > options_.max_range_m) continue;
      const Eigen::Vector3f p_cam = intrinsics.BackProject(u, v, z).cast<float>();
      const Eigen::Vector3f p = R * p_cam + t;
      cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    }
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr band(new pcl::PointCloud<pcl::PointXYZ>);
  pcl::PassThrough<pcl::PointXYZ> pass;
  pass.setInputCloud(cloud);
  pass.setFilterFieldName("z");
  pass.setFilterLimits(static_cast<float>(options_.min_height_m),
                       static_cast<float>(options_.max_height_m));
  pass.filter(*band);
  pcl::PointCloud<pcl::PointXYZ> voxels;
  if (!band->empty()) {
    pcl::VoxelGrid<pcl::PointXYZ> voxel;
    voxel.setInputCloud(band);
    const float leaf = static_cast<float>(options_.voxel_size_m);
    voxel.setLeafSize(leaf, leaf, leaf);
    voxel.filter(voxels);
  }

  // Voxels per cell in this image.
  std::vector<int> hits(grid_.size(), 0);
  std::vector<float> height_sum(grid_.size(), 0.0f);
  for (const auto& pt : voxels) {
    const Eigen::Vector3d p = T_map_base * Eigen::Vector3d(pt.x, pt.y, pt.z);
    int c = 0, r = 0;
    if (!CellOf(p.x(), p.y(), &c, &r)) continue;
    const size_t i = static_cast<size_t>(r) * cells_ + c;
    ++hits[i];
    height_sum[i] += pt.z;
  }

  // Cells in view: observed where the floor at the cell is visible (nothing in front of it),
  // cleared where the depth reaches beyond the height of their obstacle (it moved on), marked
  // where enough voxels fell in them.
  fresh_.clear();
  const Pose3 T_camera_map = (T_map_base * T_base_camera).inverse();
  // Measured depth along the ray through map point (x, y, h) and that point's own depth;
  // false when the point is out of view. A pixel without depth (nothing within the sensor's
  // range, or a dropout) measures infinity: the view reaches beyond the point.
  const auto look = [&](double x, double y, double h, double* measured, double* expected) {
    const Eigen::Vector3d pc = T_camera_map * Eigen::Vector3d(x, y, h);
    if (pc.z() < 0.3 || pc.z() > options_.max_range_m) return false;
    const Eigen::Vector2d px = intrinsics.Project(pc);
    const int u = static_cast<int>(std::lround(px.x())), v = static_cast<int>(std::lround(px.y()));
    if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) return false;
    const float d = depth_m.at<float>(v, u);
    *measured = std::isfinite(d) && d > 0.0f ? d : std::numeric_limits<double>::infinity();
    *expected = pc.z();
    return true;
  };
  for (int r = 0; r < cells_; ++r) {
    for (int c = 0; c < cells_; ++c) {
      const size_t i = static_cast<size_t>(r) * cells_ + c;
      Cell& cell = grid_[i];
      if (hits[i] >= options_.min_points_per_cell) {
        cell.last_hit_s = now;
        cell.last_seen_s = now;
        cell.height_m = height_sum[i] / hits[i];
        cell.from_scan = false;
        fresh_.push_back(CellCentre(c, r));
        continue;
      }
      const Eigen::Vector2d centre = CellCentre(c, r);
      const double x = centre.x(), y = centre.y();
      double measured = 0.0, expected = 0.0;
      if (look(x, y, 0.0, &measured, &expected) && std::isfinite(measured) &&
          measured >= expected - kSeeThroughMarginM) {
        cell.last_seen_s = now;
      }
      if (Alive(cell) && look(x, y, cell.height_m, &measured, &expected) &&
          measured > expected + kSeeThroughMarginM) {
        cell.last_seen_s = now;
        cell.last_hit_s = kNever;
      }
    }
  }
  UpdateDistance();
  return Status::Ok();
}

void ObstacleGrid::AddScan(const PlanarScan& scan, const Pose3& T_base_scanner,
                           const Pose3& T_map_base, bool same_frame) {
  const double now = scan.stamp.seconds();
  now_s_ = same_frame ? std::max(now_s_, now) : now;
  Recentre(T_map_base.translation().head<2>());
  if (!same_frame) fresh_.clear();
  const Pose3 T_map_scanner = T_map_base * T_base_scanner;
  // Returns first: their cells must not be cleared by a neighbouring beam.
  for (const Eigen::Vector2d& centre : ScanCells(scan, T_base_scanner, T_map_base)) {
    int c = 0, r = 0;
    if (!CellOf(centre.x(), centre.y(), &c, &r)) continue;
    Cell& cell = grid_[static_cast<size_t>(r) * cells_ + c];
    if (cell.last_hit_s != now_s_) fresh_.push_back(centre);
    cell.last_hit_s = now_s_;
    cell.last_seen_s = now_s_;
    cell.height_m = static_cast<float>(T_base_scanner.translation().z());
    cell.from_scan = true;
  }
  // Free space along the beams.
  const Eigen::Vector2d origin = T_map_scanner.translation().head<2>();
  const double step = 0.5 * options_.resolution_m;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float range = scan.ranges_m[i];
    const double free_m =
        std::min(options_.max_range_m, scan.IsReturn(range) ? range - kSeeThroughMarginM
                                                              : scan.range_max_m);
    if (!(free_m > 0.0)) continue;
    const double a = scan.BeamAngle(i);
    const Eigen::Vector2d dir =
        (T_map_scanner.linear() * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0)).head<2>();
    if (dir.squaredNorm() < 1e-12) continue;
    const Eigen::Vector2d unit = dir.normalized();
    for (double d = 0.0; d <= free_m; d += step) {
      const Eigen::Vector2d q = origin + d * unit;
      int c = 0, r = 0;
      if (!CellOf(q.x(), q.y(), &c, &r)) break;
      Cell& cell = grid_[static_cast<size_t>(r) * cells_ + c];
      if (cell.last_hit_s == now_s_) continue;
      cell.last_seen_s = now_s_;
      if (cell.from_scan) cell.last_hit_s = kNever;
    }
  }
  UpdateDistance();
}

std::vector<Eigen::Vector2d> ObstacleGrid::ScanCells(const PlanarScan& scan,
                                                     const Pose3& T_base_scanner,
                                                     const Pose3& T_map_base) const {
  std::vector<Eigen::Vector2d> out;
  const double height = T_base_scanner.translation().z();
  if (height < options_.min_height_m || height > options_.max_height_m) return out;
  std::vector<std::pair<int, int>> seen;
  for (const Eigen::Vector3d& p_base : ScanPointsInBase(scan, T_base_scanner)) {
    if (p_base.head<2>().norm() > options_.max_range_m) continue;
    const Eigen::Vector3d p = T_map_base * p_base;
    int c = 0, r = 0;
    if (!CellOf(p.x(), p.y(), &c, &r)) continue;
    if (std::find(seen.begin(), seen.end(), std::make_pair(c, r)) != seen.end()) continue;
    seen.emplace_back(c, r);
    out.push_back(CellCentre(c, r));
  }
  return out;
}

void ObstacleGrid::AddPoints(Time stamp, const Eigen::Vector2d& robot_xy_m,
                             const std::vector<Eigen::Vector2d>& points_m) {
  now_s_ = stamp.seconds();
  Recentre(robot_xy_m);
  fresh_.clear();
  for (const auto& p : points_m) {
    int c = 0, r = 0;
    if (!CellOf(p.x(), p.y(), &c, &r)) continue;
    fresh_.push_back(CellCentre(c, r));
    Cell& cell = grid_[static_cast<size_t>(r) * cells_ + c];
    cell.last_hit_s = now_s_;
    cell.last_seen_s = now_s_;
    cell.height_m = static_cast<float>(0.5 * (options_.min_height_m + options_.max_height_m));
    cell.from_scan = false;
  }
  UpdateDistance();
}

template <typename Visit>
void ObstacleGrid::ForEachCellIn(const Disc& d, Visit visit) const {
  if (!centred_) return;
  const double res = options_.resolution_m;
  const long c0 = static_cast<long>(std::floor((d.centre_m.x() - d.radius_m) / res));
  const long c1 = static_cast<long>(std::floor((d.centre_m.x() + d.radius_m) / res));
  const long r0 = static_cast<long>(std::floor((d.centre_m.y() - d.radius_m) / res));
  const long r1 = static_cast<long>(std::floor((d.centre_m.y() + d.radius_m) / res));
  const long last_row = origin_row_ + cells_ - 1, last_col = origin_col_ + cells_ - 1;
  for (long row = std::max(r0, origin_row_); row <= std::min(r1, last_row); ++row) {
    for (long col = std::max(c0, origin_col_); col <= std::min(c1, last_col); ++col) {
      const Eigen::Vector2d centre((col + 0.5) * res, (row + 0.5) * res);
      if ((centre - d.centre_m).norm() > d.radius_m) continue;
      visit(static_cast<size_t>(row - origin_row_) * cells_ + (col - origin_col_), centre);
    }
  }
}

ObstacleGrid ObstacleGrid::DeepCopy() const {
  ObstacleGrid out(*this);
  out.distance_m_ = distance_m_.clone();
  return out;
}

ObstacleGrid ObstacleGrid::WithDiscs(const std::vector<Disc>& discs) const {
  ObstacleGrid out = DeepCopy();
  if (!centred_ || discs.empty()) return out;
  for (const Disc& d : discs) {
    ForEachCellIn(d, [&](size_t i, const Eigen::Vector2d&) { out.grid_[i].last_hit_s = now_s_; });
  }
  out.UpdateDistance();
  return out;
}

std::vector<Eigen::Vector2d> ObstacleGrid::ObstacleCells(const Disc& area) const {
  std::vector<Eigen::Vector2d> cells;
  ForEachCellIn(area, [&](size_t i, const Eigen::Vector2d& centre) {
    if (Alive(grid_[i])) cells.push_back(centre);
  });
  return cells;
}

void ObstacleGrid::Forget(const std::vector<Eigen::Vector2d>& points_m) {
  bool changed = false;
  for (const Eigen::Vector2d& q : points_m) {
    int c = 0, r = 0;
    if (!CellOf(q.x(), q.y(), &c, &r)) continue;
    Cell& cell = grid_[static_cast<size_t>(r) * cells_ + c];
    changed = changed || Alive(cell);
    cell.last_hit_s = kNever;
  }
  if (changed) UpdateDistance();
}

ObstacleGrid ObstacleGrid::Without(const std::vector<Eigen::Vector2d>& points_m) const {
  ObstacleGrid out = DeepCopy();
  out.Forget(points_m);
  return out;
}

bool ObstacleGrid::Alive(const Cell& cell) const {
  return now_s_ - cell.last_hit_s <= options_.memory_s;
}

void ObstacleGrid::UpdateDistance() {
  cv::Mat free(cells_, cells_, CV_8U, cv::Scalar(255));
  bool any = false;
  for (int r = 0; r < cells_; ++r) {
    for (int c = 0; c < cells_; ++c) {
      if (Alive(grid_[static_cast<size_t>(r) * cells_ + c])) {
        free.at<uint8_t>(r, c) = 0;
        any = true;
      }
    }
  }
  if (!any) {
    distance_m_.setTo(max_clearance_m_);
    return;
  }
  cv::Mat dist;
  cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  // Centre-to-centre cells -> metres to the obstacle cell's near edge.
  dist = (dist - 0.5f) * static_cast<float>(options_.resolution_m);
  cv::max(dist, 0.0f, dist);
  cv::min(dist, static_cast<float>(max_clearance_m_), distance_m_);
}

bool ObstacleGrid::Obstacle(double x_m, double y_m) const {
  int c = 0, r = 0;
  if (!CellOf(x_m, y_m, &c, &r)) return false;
  return Alive(grid_[static_cast<size_t>(r) * cells_ + c]);
}

double ObstacleGrid::Clearance(double x_m, double y_m) const {
  int c = 0, r = 0;
  if (!CellOf(x_m, y_m, &c, &r)) return max_clearance_m_;
  return distance_m_.at<float>(r, c);
}

int ObstacleGrid::ObstacleCount() const {
  int n = 0;
  for (const auto& cell : grid_) n += Alive(cell) ? 1 : 0;
  return n;
}

OccupancyGrid ObstacleGrid::Export() const {
  OccupancyGrid out;
  out.resolution_m = options_.resolution_m;
  out.width = cells_;
  out.height = cells_;
  out.origin_m = Eigen::Vector2d(origin_col_, origin_row_) * options_.resolution_m;
  out.data.assign(grid_.size(), -1);
  if (!centred_) return out;
  for (int r = 0; r < cells_; ++r) {
    for (int c = 0; c < cells_; ++c) {
      const size_t i = static_cast<size_t>(r) * cells_ + c;
      if (Alive(grid_[i])) {
        out.data[i] = 100;
      } else if (distance_m_.at<float>(r, c) < inflation_m()) {
        out.data[i] = 99;
      } else if (grid_[i].last_seen_s > kNever) {
        out.data[i] = 0;
      }
    }
  }
  return out;
}

}  // namespace icgm

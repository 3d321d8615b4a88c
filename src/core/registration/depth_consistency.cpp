#include "core/registration/depth_consistency.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/common/option_reader.h"
#include "core/registration/dynamic_region_fill.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, DepthConsistencyOptions* options) {
  reader.Read("grid_step_px", &options->grid_step_px, 1, 64);
  reader.Read("abs_tolerance_m", &options->abs_tolerance_m, 0.0, 1.0);
  reader.Read("rel_tolerance_per_m", &options->rel_tolerance_per_m, 0.0, 1.0);
  reader.Read("min_depth_m", &options->min_depth_m, 0.0, 100.0);
  reader.Read("max_depth_m", &options->max_depth_m, 0.0, 100.0);
  reader.Read("min_neighbours", &options->min_neighbours, 1, 9);
  reader.Read("dilate_cells", &options->dilate_cells, 0, 64);
  reader.Read("min_gradient", &options->min_gradient, 0.0, 255.0);
  reader.Read("grey_tolerance", &options->grey_tolerance, 0.0, 255.0);
  reader.Read("mask_behind", &options->mask_behind);
  reader.Read("fill_max_step_m", &options->fill_max_step_m, 0.0, 10.0);
  reader.Read("fill_band_m", &options->fill_band_m, 0.0, 100.0);
}

bool DynamicMask::Contains(const cv::Point2f& px) const {
  if (cells.empty()) return false;
  const int c = static_cast<int>(px.x) / step_px;
  const int r = static_cast<int>(px.y) / step_px;
  if (px.x < 0 || px.y < 0 || r >= cells.rows || c >= cells.cols) return false;
  return cells.at<uint8_t>(r, c) != 0;
}

double DynamicMask::Coverage() const {
  if (cells.empty()) return 0.0;
  return static_cast<double>(cv::countNonZero(cells)) / static_cast<double>(cells.total());
}

namespace {

// Keeps cells with enough marked neighbours, grows them over their surface in `depth_m`
// (fill_max_step_m > 0), then dilates them.
cv::Mat CleanAndGrow(const cv::Mat& raw, const cv::Mat& depth_m, const DepthConsistencyOptions& o) {
  const int min_neighbours = o.min_neighbours, dilate_cells = o.dilate_cells;
  cv::Mat ones;
  raw.convertTo(ones, CV_8U, 1.0 / 255.0);
  cv::Mat counts;
  cv::boxFilter(ones, counts, CV_8U, cv::Size(3, 3), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  cv::Mat kept = (counts >= min_neighbours) & raw;
  if (o.fill_max_step_m > 0.0) {
    kept = FillConnectedSurface(kept, depth_m, std::max(1, o.grid_step_px),
                                {o.fill_max_step_m, o.fill_band_m, o.min_depth_m, o.max_depth_m});
  }
  if (dilate_cells > 0) {
    const cv::Mat kernel = cv::getStructuringElement(
        cv::MORPH_ELLIPSE, cv::Size(2 * dilate_cells + 1, 2 * dilate_cells + 1));
    cv::dilate(kept, kept, kernel);
  }
  return kept;
}

}  // namespace

DepthConsistency CheckDepthConsistency(const cv::Mat& depth_ref_m, const cv::Mat& depth_cur_m,
                                       const Pose3& ref_cur, const CameraIntrinsics& k,
                                       const DepthConsistencyOptions& o, DynamicMask* mask,
                                       DynamicMask* reference_mask) {
  DepthConsistency out;
  const int step = std::max(1, o.grid_step_px);
  for (DynamicMask* m : {mask, reference_mask}) {
    if (!m) continue;
    m->cells.release();
    m->step_px = step;
  }
  if (depth_ref_m.empty() || depth_cur_m.empty() || depth_ref_m.type() != CV_32FC1 ||
      depth_cur_m.type() != CV_32FC1) {
    return out;
  }
  const int rows = (depth_cur_m.rows + step - 1) / step;
  const int cols = (depth_cur_m.cols + step - 1) / step;
  cv::Mat raw, raw_ref;
  if (mask) raw = cv::Mat::zeros(rows, cols, CV_8UC1);
  if (reference_mask) {
    raw_ref = cv::Mat::zeros((depth_ref_m.rows + step - 1) / step,
                             (depth_ref_m.cols + step - 1) / step, CV_8UC1);
  }
  const Eigen::Matrix3f r = ref_cur.linear().cast<float>();
  const Eigen::Vector3f t = ref_cur.translation().cast<float>();
  const float fx = static_cast<float>(k.fx_px), fy = static_cast<float>(k.fy_px);
  const float cx = static_cast<float>(k.cx_px), cy = static_cast<float>(k.cy_px);
  for (int gv = 0; gv < rows; ++gv) {
    const int v = gv * step;
    const float* row = depth_cur_m.ptr<float>(v);
    const float y_over_z = (static_cast<float>(v) - cy) / fy;
    for (int gu = 0; gu < cols; ++gu) {
      const int u = gu * step;
      const float z = row[u];
      if (!o.Usable(z)) continue;
      const Eigen::Vector3f p =
          r * Eigen::Vector3f((static_cast<float>(u) - cx) / fx * z, y_over_z * z, z) + t;
      if (p.z() <= 1e-3f) continue;
      const int ur = static_cast<int>(std::lround(fx * p.x() / p.z() + cx));
      const int vr = static_cast<int>(std::lround(fy * p.y() / p.z() + cy));
      if (ur < 0 || vr < 0 || ur >= depth_ref_m.cols || vr >= depth_ref_m.rows) continue;
      const float zr = depth_ref_m.at<float>(vr, ur);
      if (!o.Usable(zr)) continue;
      ++out.compared;
      const double tol = o.Tolerance(p.z());
      const double residual = double(zr) - double(p.z());  // > 0: current point in front
      if (std::abs(residual) <= tol) {
        ++out.agreeing;
      } else if (residual > 0) {
        ++out.in_front;
        if (mask) raw.at<uint8_t>(gv, gu) = 255;
      } else {
        ++out.behind;
        if (reference_mask) raw_ref.at<uint8_t>(vr / step, ur / step) = 255;
        if (mask && o.mask_behind) raw.at<uint8_t>(gv, gu) = 255;
      }
    }
  }
  if (mask) mask->cells = CleanAndGrow(raw, depth_cur_m, o);
  if (reference_mask) {
    reference_mask->cells = CleanAndGrow(raw_ref, depth_ref_m, o);
  }
  return out;
}

DepthConsistency CheckEdgeConsistency(const cv::Mat& grey_ref, const cv::Mat& grey_cur,
                                      const cv::Mat& depth_cur_m, const Pose3& ref_cur,
                                      const CameraIntrinsics& k,
                                      const DepthConsistencyOptions& o) {
  DepthConsistency out;
  if (grey_ref.empty() || grey_cur.empty() || depth_cur_m.empty() ||
      grey_ref.type() != CV_8UC1 || grey_cur.type() != CV_8UC1 ||
      depth_cur_m.type() != CV_32FC1 || grey_cur.size() != depth_cur_m.size()) {
    return out;
  }
  const int step = std::max(1, o.grid_step_px);
  const Eigen::Matrix3f r = ref_cur.linear().cast<float>();
  const Eigen::Vector3f t = ref_cur.translation().cast<float>();
  const float fx = static_cast<float>(k.fx_px), fy = static_cast<float>(k.fy_px);
  const float cx = static_cast<float>(k.cx_px), cy = static_cast<float>(k.cy_px);
  for (int v = step; v + 1 < depth_cur_m.rows; v += step) {
    const uint8_t* g = grey_cur.ptr<uint8_t>(v);
    const uint8_t* up = grey_cur.ptr<uint8_t>(v - 1);
    const uint8_t* down = grey_cur.ptr<uint8_t>(v + 1);
    const float* zrow = depth_cur_m.ptr<float>(v);
    for (int u = step; u + 1 < depth_cur_m.cols; u += step) {
      const float gx = float(g[u + 1]) - float(g[u - 1]);
      const float gy = float(down[u]) - float(up[u]);
      if (std::abs(gx) + std::abs(gy) < o.min_gradient) continue;
      const float z = zrow[u];
      if (!o.Usable(z)) continue;
      const Eigen::Vector3f p = r * Eigen::Vector3f((float(u) - cx) / fx * z,
                                                    (float(v) - cy) / fy * z, z) + t;
      if (p.z() <= 1e-3f) continue;
      const int ur = static_cast<int>(std::lround(fx * p.x() / p.z() + cx));
      const int vr = static_cast<int>(std::lround(fy * p.y() / p.z() + cy));
      if (ur < 0 || vr < 0 || ur >= grey_ref.cols || vr >= grey_ref.rows) continue;
      ++out.compared;
      if (std::abs(float(grey_ref.at<uint8_t>(vr, ur)) - float(g[u])) <= o.grey_tolerance) {
        ++out.agreeing;
      }
    }
  }
  return out;
}

DynamicMask PropagateDynamicMask(const DynamicMask& previous, const cv::Mat& depth_prev_m,
                                 const Pose3& cur_prev, const CameraIntrinsics& k,
                                 int grow_cells) {
  DynamicMask out;
  out.step_px = previous.step_px;
  if (previous.empty()) return out;
  cv::Mat moved = cv::Mat::zeros(previous.cells.size(), CV_8UC1);
  const bool has_depth = !depth_prev_m.empty() && depth_prev_m.type() == CV_32FC1;
  const int step = previous.step_px;
  for (int gv = 0; gv < previous.cells.rows; ++gv) {
    for (int gu = 0; gu < previous.cells.cols; ++gu) {
      if (!previous.cells.at<uint8_t>(gv, gu)) continue;
      const int u = gu * step, v = gv * step;
      float z = has_depth && v < depth_prev_m.rows && u < depth_prev_m.cols
                    ? depth_prev_m.at<float>(v, u)
                    : 0.0f;
      int tu = gu, tv = gv;
      if (std::isfinite(z) && z > 0.0f) {
        const Eigen::Vector3d p = cur_prev * k.BackProject(u, v, z);
        if (p.z() > 1e-3) {
          const Eigen::Vector2d px = k.Project(p);
          tu = static_cast<int>(std::lround(px.x() / step));
          tv = static_cast<int>(std::lround(px.y() / step));
        }
      }
      if (tu >= 0 && tv >= 0 && tu < moved.cols && tv < moved.rows) moved.at<uint8_t>(tv, tu) = 255;
    }
  }
  // Closing fills the holes left by forward mapping before growing.
  const cv::Mat small = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::morphologyEx(moved, moved, cv::MORPH_CLOSE, small);
  if (grow_cells > 0) {
    const cv::Mat kernel = cv::getStructuringElement(
        cv::MORPH_ELLIPSE, cv::Size(2 * grow_cells + 1, 2 * grow_cells + 1));
    cv::dilate(moved, moved, kernel);
  }
  out.cells = moved;
  return out;
}

}  // namespace icgm

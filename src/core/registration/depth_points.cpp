#include "core/registration/depth_points.h"

#include <cmath>
#include <sstream>

namespace icgm {

cv::Mat CorrectedDepth(const cv::Mat& depth_m, const CameraIntrinsics& intrinsics) {
  if (intrinsics.depth_correction == 1.0 || depth_m.type() != CV_32FC1) return depth_m;
  return depth_m * intrinsics.depth_correction;
}

DepthRejectCounts& DepthRejectCounts::operator+=(const DepthRejectCounts& o) {
  outside_image += o.outside_image;
  missing += o.missing;
  out_of_range += o.out_of_range;
  discontinuity += o.discontinuity;
  return *this;
}

std::string DepthRejectCounts::ToString() const {
  std::ostringstream s;
  s << "missing " << missing << ", out of range " << out_of_range << ", discontinuity "
    << discontinuity << ", outside image " << outside_image;
  return s.str();
}

namespace {
bool Measured(float z) { return std::isfinite(z) && z > 0.0f; }
}  // namespace

DepthLookup LookupDepth(const cv::Mat& depth_m, const cv::Point2f& px,
                        const DepthPointOptions& options, double* z_m) {
  if (depth_m.empty() || depth_m.type() != CV_32FC1) return DepthLookup::kMissing;
  if (!std::isfinite(px.x) || !std::isfinite(px.y)) return DepthLookup::kOutsideImage;
  const int u = static_cast<int>(std::lround(px.x));
  const int v = static_cast<int>(std::lround(px.y));
  if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) return DepthLookup::kOutsideImage;
  const float z = depth_m.at<float>(v, u);
  if (!Measured(z)) return DepthLookup::kMissing;
  if (z < options.min_depth_m || z > options.max_depth_m) return DepthLookup::kOutOfRange;
  if (options.max_depth_jump_ratio > 0.0) {
    const float max_jump = static_cast<float>(options.max_depth_jump_ratio) * z;
    for (int dv = -1; dv <= 1; ++dv) {
      const int vv = v + dv;
      if (vv < 0 || vv >= depth_m.rows) continue;
      const float* row = depth_m.ptr<float>(vv);
      for (int du = -1; du <= 1; ++du) {
        const int uu = u + du;
        if (uu < 0 || uu >= depth_m.cols) continue;
        const float zn = row[uu];
        // A hole next to the pixel usually means a shadow edge of the structured-light sensor.
        if (!Measured(zn) || std::fabs(zn - z) > max_jump) return DepthLookup::kDiscontinuity;
      }
    }
  }
  *z_m = z;
  return DepthLookup::kOk;
}

void CountReject(DepthLookup result, DepthRejectCounts* counts) {
  switch (result) {
    case DepthLookup::kOk:
      break;
    case DepthLookup::kOutsideImage:
      ++counts->outside_image;
      break;
    case DepthLookup::kMissing:
      ++counts->missing;
      break;
    case DepthLookup::kOutOfRange:
      ++counts->out_of_range;
      break;
    case DepthLookup::kDiscontinuity:
      ++counts->discontinuity;
      break;
  }
}

void KeypointsToPoints(const std::vector<cv::Point2f>& pixels, const cv::Mat& depth_m,
                       const CameraIntrinsics& intrinsics, const DepthPointOptions& options,
                       std::vector<Eigen::Vector3d>* points, std::vector<uint8_t>* valid,
                       DepthRejectCounts* counts) {
  points->assign(pixels.size(), Eigen::Vector3d::Zero());
  valid->assign(pixels.size(), 0);
  for (size_t i = 0; i < pixels.size(); ++i) {
    double z = 0.0;
    const DepthLookup r = LookupDepth(depth_m, pixels[i], options, &z);
    if (r != DepthLookup::kOk) {
      if (counts) CountReject(r, counts);
      continue;
    }
    (*points)[i] = intrinsics.BackProject(pixels[i].x, pixels[i].y, z);
    (*valid)[i] = 1;
  }
}

}  // namespace icgm

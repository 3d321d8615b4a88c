#include "core/map/keyframe_images.h"

#include <cmath>

namespace icgm {

KeyframeImages DownsampleKeyframeImages(const cv::Mat& bgr, const cv::Mat& depth_m,
                                        const CameraIntrinsics& intrinsics, int factor) {
  KeyframeImages out;
  if (depth_m.empty() || depth_m.type() != CV_32FC1 || factor < 1) return out;
  const int offset = factor / 2;
  const int cols = (depth_m.cols - offset + factor - 1) / factor;
  const int rows = (depth_m.rows - offset + factor - 1) / factor;
  out.downsample = factor;
  out.depth_mm = cv::Mat(rows, cols, CV_16UC1, cv::Scalar(0));
  const bool colour = !bgr.empty() && bgr.type() == CV_8UC3 && bgr.size() == depth_m.size();
  if (colour) out.bgr = cv::Mat(rows, cols, CV_8UC3, cv::Scalar::all(0));
  for (int v = 0; v < rows; ++v) {
    const int y = v * factor + offset;
    for (int u = 0; u < cols; ++u) {
      const int x = u * factor + offset;
      const float z = depth_m.at<float>(y, x);
      if (std::isfinite(z) && z > 0.0f && z < 65.5f) {
        out.depth_mm.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(z * 1000.0f));
      }
      if (colour) out.bgr.at<cv::Vec3b>(v, u) = bgr.at<cv::Vec3b>(y, x);
    }
  }
  // Stored pixel u sees what full pixel u * f + offset sees: x = f * u + offset.
  CameraIntrinsics k = intrinsics;
  k.fx_px = intrinsics.fx_px / factor;
  k.fy_px = intrinsics.fy_px / factor;
  k.cx_px = (intrinsics.cx_px - offset) / factor;
  k.cy_px = (intrinsics.cy_px - offset) / factor;
  k.width_px = cols;
  k.height_px = rows;
  k.distortion_k1 = k.distortion_k2 = k.distortion_p1 = k.distortion_p2 = k.distortion_k3 = 0.0;
  out.intrinsics = k;
  return out;
}

}  // namespace icgm

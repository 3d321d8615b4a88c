// Software registration of a depth image to the colour camera, for a device that cannot register
// in hardware: each depth pixel is back-projected with the depth (IR) camera's intrinsics, moved
// into the colour camera's frame by the extrinsic, and projected into the colour image; where
// several land on one colour pixel the nearest surface wins (z-buffer). Each depth pixel fills the
// colour pixels its footprint covers (the projections of its corners), so a colour camera that
// magnifies more than the depth camera gets no cracks. The result has the colour image's size and
// holds millimetres along the colour camera's z axis, 0 where no depth landed.
// Cost: the rays through the depth pixels' corners are precomputed per column and row; each row
// is projected in one branch-free pass (vectorised) with integer rounding, then the valid pixels
// are splatted into the z-buffer (about 3 ms CPU for a 640x480 frame on one loaded core).
//
// Calibration: DepthCameraCalibration, the `depth_camera` section of a camera YAML
// (core/dataset/camera_options.h).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/dataset/camera_options.h"
#include "core/common/option_reader.h"
#include "core/common/pose.h"

namespace icgm {

// Reads the `depth_camera` section of a camera YAML into `out`; false when the file has none.
// Throws LoadError when the file is unreadable or invalid anywhere (LoadCameraIntrinsics).
bool LoadDepthCameraCalibration(const std::string& yaml_path, DepthCameraCalibration* out);

class DepthRegistration {
 public:
  DepthRegistration(const DepthCameraCalibration& calibration, const CameraIntrinsics& color);

  // depth_mm: CV_16UC1 of the depth camera's size (0 = no depth). Returns CV_16UC1 of the colour
  // camera's size. An image of another size or type gives an empty Mat.
  cv::Mat Register(const cv::Mat& depth_mm) const;

 private:
  DepthCameraCalibration calibration_;
  CameraIntrinsics color_;
  // The colour-frame direction of the ray through a depth pixel corner (u - 1/2, v - 1/2) is
  // column[u] + row[v] (one more than pixels each way): x R0 and y R1 + R2, by component.
  std::vector<float> column_x_, column_y_, column_z_;
  std::vector<float> row_x_, row_y_, row_z_;
};

}  // namespace icgm

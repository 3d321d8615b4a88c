// Pinhole intrinsics of the RGB-D camera (registered depth shares them).
#pragma once

#include <Eigen/Core>

namespace icgm {

struct CameraIntrinsics {
  double fx_px = 525.0;
  double fy_px = 525.0;
  double cx_px = 319.5;
  double cy_px = 239.5;
  int width_px = 640;
  int height_px = 480;
  // Depth image value -> metres: depth_m = value / depth_scale (5000 for TUM PNG, 1000 for mm).
  double depth_scale = 1000.0;
  // Capture instant of a depth image minus its stamp, relative to the same for the colour image
  // (s). Sensors whose colour and depth streams are stamped on arrival with different latencies
  // (Kinect v1) capture depth this much earlier (< 0) than its stamp says, compared with colour.
  double depth_time_offset_s = 0.0;
  // Calibrated scale of the sensor's depth: every depth (metres) is multiplied by it before use.
  // The TUM benchmark publishes 1.035 for its Freiburg 1 Kinect (the raw depth reads 3.5% short).
  double depth_correction = 1.0;
  // Rolling shutter (core/registration/rolling_shutter.h): time from the capture of the first
  // image row to that of the last (s); 0 for a global shutter. The registered depth image is
  // taken to share the colour image's row timing, shifted by depth_time_offset_s.
  double readout_s = 0.0;
  // Capture instant of the first row minus the image's stamp (s).
  double first_row_offset_s = 0.0;
  // Radial-tangential (Brown-Conrady, OpenCV / ROS plumb_bob order k1 k2 p1 p2 k3) distortion of
  // the colour camera; the registered depth shares the colour pixels. The front end resamples
  // both images (or, for features extracted elsewhere, the keypoints) to the ideal pinhole
  // camera of fx/fy/cx/cy before use.
  double distortion_k1 = 0.0;
  double distortion_k2 = 0.0;
  double distortion_p1 = 0.0;
  double distortion_p2 = 0.0;
  double distortion_k3 = 0.0;

  bool HasDistortion() const {
    return distortion_k1 != 0.0 || distortion_k2 != 0.0 || distortion_p1 != 0.0 ||
           distortion_p2 != 0.0 || distortion_k3 != 0.0;
  }

  bool Valid() const {
    return fx_px > 0 && fy_px > 0 && width_px > 0 && height_px > 0 && depth_scale > 0 &&
           depth_correction > 0;
  }
  // Back-projects pixel (u, v) at depth z_m into the camera frame (x right, y down, z forward).
  Eigen::Vector3d BackProject(double u, double v, double z_m) const {
    return {(u - cx_px) * z_m / fx_px, (v - cy_px) * z_m / fy_px, z_m};
  }
  Eigen::Vector2d Project(const Eigen::Vector3d& p) const {
    return {fx_px * p.x() / p.z() + cx_px, fy_px * p.y() / p.z() + cy_px};
  }
};

}  // namespace icgm

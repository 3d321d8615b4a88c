// A TUM RGB-D benchmark sequence folder (Sturm et al., IROS 2012): rgb.txt and depth.txt list
// "timestamp relative/path" per line, groundtruth.txt (optional) is a TUM trajectory. Colour
// and depth frames are associated one-to-one by nearest timestamp like the benchmark's
// associate.py: candidate pairs within max_association_dt_s are accepted greedily in order
// of increasing time difference, each image used at most once.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/time.h"
#include "core/dataset/trajectory.h"

namespace icgm {

struct RgbdFrameRef {
  Time stamp;            // colour image stamp (the frame's stamp)
  Time depth_stamp;      // associated depth image stamp
  std::string rgb_path;  // absolute or relative to the working directory
  std::string depth_path;
};

class TumDataset {
 public:
  // Reads the index files of `dir`. Throws LoadError for a missing folder or index file, a
  // malformed line (file:line named), an image listed but absent, invalid intrinsics or a
  // negative max_association_dt_s. Frames are sorted by colour stamp.
  static TumDataset Open(const std::string& dir, const CameraIntrinsics& intrinsics,
                         double max_association_dt_s = 0.02);

  size_t size() const { return frames_.size(); }
  // i < size() (asserted).
  const RgbdFrameRef& frame(size_t i) const;
  // Colour image, CV_8UC3 BGR; throws LoadError if unreadable or not of the intrinsics' size.
  cv::Mat LoadBgr(size_t i) const;
  // Depth as ToMetricDepth(png, intrinsics().depth_scale): CV_32FC1 metres, NaN invalid;
  // throws LoadError if unreadable, not 16-bit/float single channel or not of the
  // intrinsics' size.
  cv::Mat LoadDepthM(size_t i) const;

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const std::string& directory() const { return dir_; }
  bool has_groundtruth() const { return !groundtruth_.empty(); }
  // Empty when the folder has no groundtruth.txt.
  const Trajectory& groundtruth() const { return groundtruth_; }
  // Colour images listed in rgb.txt that found no depth partner.
  size_t unmatched_rgb() const { return unmatched_rgb_; }

 private:
  TumDataset() = default;
  std::string dir_;
  CameraIntrinsics intrinsics_;
  std::vector<RgbdFrameRef> frames_;
  Trajectory groundtruth_;
  size_t unmatched_rgb_ = 0;
};

}  // namespace icgm

#include "core/common/image_size.h"

namespace icgm {

Status CheckImageSize(const CameraIntrinsics& k, const std::string& calibration, int width_px,
                      int height_px, const std::string& image) {
  if (k.width_px == width_px && k.height_px == height_px) return Status::Ok();
  return Status::Error("'" + calibration + "' is calibrated for " + std::to_string(k.width_px) +
                       "x" + std::to_string(k.height_px) + " images, " + image + " " +
                       std::to_string(width_px) + "x" + std::to_string(height_px));
}

}  // namespace icgm

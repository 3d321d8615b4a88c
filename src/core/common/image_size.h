// The one check that an image fits the intrinsics it is combined with (a camera YAML, a
// camera_info): intrinsics of another size would back-project every pixel with the wrong focal
// length and centre, silently giving wrong 3-D points and poses.
#pragma once

#include <string>

#include "core/common/camera.h"
#include "core/common/status.h"

namespace icgm {

// Whether an image of width_px x height_px (`image` says where it comes from, e.g. "the device
// streams" or "'/camera/rgb/image_color' carries") fits `k`, calibrated (by `calibration`, e.g. a
// camera YAML or a camera_info topic) for images of its own size. The error names both sizes.
Status CheckImageSize(const CameraIntrinsics& k, const std::string& calibration, int width_px,
                      int height_px, const std::string& image);

}  // namespace icgm

// The frames of a TUM RGB-D folder as the streams of an RGB-D device: colour (RGB888, as OpenNI
// delivers it) and depth (uint16 millimetres, registered, as a Kinect with hardware
// registration gives it), each stamped on a device clock that starts at 1 ms at the sequence's
// first image and keeps the recording's spacing. Events are in device time order, colour i at
// its stamp and depth i at its own stamp, so the depth-colour offsets of the recording are kept.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/dataset/tum_dataset.h"
#include "core/sensor/virtual_device_uri.h"
#include "core/sensor/virtual_frame_source.h"

namespace icgm {

class TumFrameSource : public VirtualFrameSource {
 public:
  // Fails with the dataset's or camera file's reason.
  static Status Open(const VirtualDeviceConfig& config, std::unique_ptr<TumFrameSource>* out);

  const std::vector<FrameEvent>& events() const override { return events_; }
  cv::Mat Load(const FrameEvent& event, std::string* error) override;
  const CameraIntrinsics& intrinsics() const override { return intrinsics_; }
  const VirtualDeviceConfig& config() const override { return config_; }

 private:
  TumFrameSource(TumDataset dataset, VirtualDeviceConfig config);
  TumDataset dataset_;
  VirtualDeviceConfig config_;
  CameraIntrinsics intrinsics_;
  Time first_;
  std::vector<FrameEvent> events_;
};

}  // namespace icgm

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

namespace icgm {

struct FrameEvent {
  bool color = true;
  size_t frame = 0;        // index in the dataset
  uint64_t device_us = 0;  // device clock
};

class TumFrameSource {
 public:
  // Fails with the dataset's or camera file's reason.
  static Status Open(const VirtualDeviceConfig& config, std::unique_ptr<TumFrameSource>* out);

  const std::vector<FrameEvent>& events() const { return events_; }
  // RGB CV_8UC3 (colour) or CV_16UC1 mm (depth); empty with *error set when unreadable.
  cv::Mat Load(const FrameEvent& event, std::string* error) const;
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const VirtualDeviceConfig& config() const { return config_; }
  // Device stamp of the event, the way the OpenNI device reports it for a TUM stamp.
  uint64_t DeviceMicros(Time stamp) const;

 private:
  TumFrameSource(TumDataset dataset, VirtualDeviceConfig config);
  TumDataset dataset_;
  VirtualDeviceConfig config_;
  CameraIntrinsics intrinsics_;
  Time first_;
  std::vector<FrameEvent> events_;
};

}  // namespace icgm

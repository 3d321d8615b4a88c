// What the project's virtual OpenNI2 device plays: colour and depth images, each an event on the
// device clock (microseconds, starting at 1 ms), delivered as a Kinect with hardware
// registration would (colour RGB888, depth uint16 millimetres registered to colour). Sources: a
// TUM RGB-D folder (tum_frame_source.h) or a simulated scenario (sim_frame_source.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/camera.h"
#include "core/common/status.h"
#include "core/common/time.h"
#include "core/sensor/virtual_device_uri.h"

namespace icgm {

struct FrameEvent {
  bool color = true;
  size_t frame = 0;        // index in the source
  uint64_t device_us = 0;  // device clock
};

class VirtualFrameSource {
 public:
  virtual ~VirtualFrameSource() = default;
  // In device time order.
  virtual const std::vector<FrameEvent>& events() const = 0;
  // RGB CV_8UC3 (colour) or CV_16UC1 mm (depth); empty with *error set when unavailable.
  // Called from one thread at a time.
  virtual cv::Mat Load(const FrameEvent& event, std::string* error) = 0;
  virtual const CameraIntrinsics& intrinsics() const = 0;
  virtual const VirtualDeviceConfig& config() const = 0;
};

// The source the URI's configuration names; fails with the dataset's or scenario's reason.
Status OpenVirtualFrameSource(const VirtualDeviceConfig& config,
                              std::unique_ptr<VirtualFrameSource>* out);

// The device's images from the project's: BGR -> RGB; metres (NaN invalid) -> millimetres (0).
cv::Mat DeviceColour(const cv::Mat& bgr);
cv::Mat DeviceDepthMm(const cv::Mat& depth_m);
// Device clock of a stamp for a source whose first event is at `first`.
uint64_t DeviceMicros(Time first, Time stamp);

}  // namespace icgm

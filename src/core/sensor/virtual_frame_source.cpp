#include "core/sensor/virtual_frame_source.h"

#include <opencv2/imgproc.hpp>

#include "core/sensor/sim_frame_source.h"
#include "core/sensor/tum_frame_source.h"

namespace icgm {

Status OpenVirtualFrameSource(const VirtualDeviceConfig& config,
                              std::unique_ptr<VirtualFrameSource>* out) {
  Status status = Status::Ok();
  if (config.source == "sim") {
    std::unique_ptr<SimFrameSource> sim;
    status = SimFrameSource::Open(config, &sim);
    *out = std::move(sim);
  } else {
    std::unique_ptr<TumFrameSource> tum;
    status = TumFrameSource::Open(config, &tum);
    *out = std::move(tum);
  }
  return status;
}

cv::Mat DeviceColour(const cv::Mat& bgr) {
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

cv::Mat DeviceDepthMm(const cv::Mat& depth_m) {
  cv::Mat m = depth_m.clone();
  cv::patchNaNs(m, 0.0);
  cv::Mat mm;
  m.convertTo(mm, CV_16UC1, 1000.0);
  return mm;
}

uint64_t DeviceMicros(Time first, Time stamp) {
  return 1000 + static_cast<uint64_t>((stamp.nanoseconds() - first.nanoseconds()) / 1000);
}

}  // namespace icgm

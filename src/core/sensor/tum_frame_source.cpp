#include "core/sensor/tum_frame_source.h"

#include <algorithm>
#include <cmath>

#include "core/dataset/camera_options.h"

namespace icgm {

TumFrameSource::TumFrameSource(TumDataset dataset, VirtualDeviceConfig config)
    : dataset_(std::move(dataset)), config_(std::move(config)), intrinsics_(dataset_.intrinsics()) {}

Status TumFrameSource::Open(const VirtualDeviceConfig& config,
                            std::unique_ptr<TumFrameSource>* out) {
  try {
    CameraIntrinsics k;
    k.depth_scale = 5000.0;  // TUM depth PNGs
    if (!config.camera_yaml.empty()) k = LoadCameraIntrinsics(config.camera_yaml);
    TumDataset dataset = TumDataset::Open(config.dir, k);
    if (dataset.size() == 0) return Status::Error("TUM folder '" + config.dir + "' has no frames");
    std::unique_ptr<TumFrameSource> source(new TumFrameSource(std::move(dataset), config));
    const size_t n = config.max_frames > 0
                         ? std::min<size_t>(source->dataset_.size(), config.max_frames)
                         : source->dataset_.size();
    source->first_ = std::min(source->dataset_.frame(0).stamp, source->dataset_.frame(0).depth_stamp);
    for (size_t i = 0; i < n; ++i) {
      const RgbdFrameRef& f = source->dataset_.frame(i);
      source->events_.push_back({true, i, DeviceMicros(source->first_, f.stamp)});
      source->events_.push_back({false, i, DeviceMicros(source->first_, f.depth_stamp)});
    }
    std::stable_sort(source->events_.begin(), source->events_.end(),
                     [](const FrameEvent& a, const FrameEvent& b) { return a.device_us < b.device_us; });
    *out = std::move(source);
    return Status::Ok();
  } catch (const LoadError& e) {
    return Status::Error(e.what());
  }
}

cv::Mat TumFrameSource::Load(const FrameEvent& event, std::string* error) {
  try {
    return event.color ? DeviceColour(dataset_.LoadBgr(event.frame))
                       : DeviceDepthMm(dataset_.LoadDepthM(event.frame));
  } catch (const LoadError& e) {
    *error = e.what();
    return cv::Mat();
  }
}

}  // namespace icgm

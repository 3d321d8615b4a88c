#include "core/sensor/tum_frame_source.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

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
      source->events_.push_back({true, i, source->DeviceMicros(f.stamp)});
      source->events_.push_back({false, i, source->DeviceMicros(f.depth_stamp)});
    }
    std::stable_sort(source->events_.begin(), source->events_.end(),
                     [](const FrameEvent& a, const FrameEvent& b) { return a.device_us < b.device_us; });
    *out = std::move(source);
    return Status::Ok();
  } catch (const LoadError& e) {
    return Status::Error(e.what());
  }
}

uint64_t TumFrameSource::DeviceMicros(Time stamp) const {
  return 1000 + static_cast<uint64_t>((stamp.nanoseconds() - first_.nanoseconds()) / 1000);
}

cv::Mat TumFrameSource::Load(const FrameEvent& event, std::string* error) const {
  try {
    cv::Mat out;
    if (event.color) {
      cv::cvtColor(dataset_.LoadBgr(event.frame), out, cv::COLOR_BGR2RGB);
    } else {
      // Metres (NaN invalid) -> millimetres (0 invalid), as the device reports them.
      cv::Mat m = dataset_.LoadDepthM(event.frame);
      cv::patchNaNs(m, 0.0);
      m.convertTo(out, CV_16UC1, 1000.0);
    }
    return out;
  } catch (const LoadError& e) {
    *error = e.what();
    return cv::Mat();
  }
}

}  // namespace icgm

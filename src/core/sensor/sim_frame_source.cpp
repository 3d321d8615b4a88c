#include "core/sensor/sim_frame_source.h"

#include <algorithm>

#include "core/common/option_reader.h"
#include "core/sim/sim_options.h"

namespace icgm {

SimFrameSource::SimFrameSource(std::unique_ptr<sim::Simulator> simulator,
                               VirtualDeviceConfig config)
    : simulator_(std::move(simulator)), config_(std::move(config)) {}

Status SimFrameSource::Open(const VirtualDeviceConfig& config,
                            std::unique_ptr<SimFrameSource>* out) {
  try {
    auto simulator = std::make_unique<sim::Simulator>(sim::LoadSimOptions(config.scenario));
    std::unique_ptr<SimFrameSource> source(new SimFrameSource(std::move(simulator), config));
    const sim::Simulator& s = *source->simulator_;
    const size_t n = config.max_frames > 0 ? std::min<size_t>(s.size(), config.max_frames)
                                           : s.size();
    for (size_t i = 0; i < n; ++i) {
      const uint64_t us = DeviceMicros(s.stamp(0), s.stamp(i));
      source->events_.push_back({true, i, us});
      source->events_.push_back({false, i, us});
    }
    *out = std::move(source);
    return Status::Ok();
  } catch (const LoadError& e) {
    return Status::Error(std::string("simulated scenario: ") + e.what());
  }
}

cv::Mat SimFrameSource::Load(const FrameEvent& event, std::string* error) {
  if (event.frame >= simulator_->size()) {
    *error = "frame " + std::to_string(event.frame) + " beyond the scenario";
    return cv::Mat();
  }
  if (!rendered_ || rendered_->index != event.frame) rendered_ = simulator_->Render(event.frame);
  return event.color ? DeviceColour(rendered_->bgr) : DeviceDepthMm(rendered_->depth_m);
}

}  // namespace icgm

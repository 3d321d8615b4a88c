// A simulated scenario (config/sim/*.yaml, core/sim) as the streams of an RGB-D device: each
// frame rendered when its colour event is due, colour and depth on the frame's stamp (the
// simulator renders registered depth at the colour instant), device clock from 1 ms at the first
// frame. Lets the driver nodelet and everything after it run on a scenario with ground truth.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/sensor/virtual_frame_source.h"
#include "core/sim/simulator.h"

namespace icgm {

class SimFrameSource : public VirtualFrameSource {
 public:
  // Fails with the scenario file's reason.
  static Status Open(const VirtualDeviceConfig& config, std::unique_ptr<SimFrameSource>* out);

  const std::vector<FrameEvent>& events() const override { return events_; }
  cv::Mat Load(const FrameEvent& event, std::string* error) override;
  const CameraIntrinsics& intrinsics() const override { return simulator_->intrinsics(); }
  const VirtualDeviceConfig& config() const override { return config_; }
  const sim::Simulator& simulator() const { return *simulator_; }

 private:
  SimFrameSource(std::unique_ptr<sim::Simulator> simulator, VirtualDeviceConfig config);
  std::unique_ptr<sim::Simulator> simulator_;
  VirtualDeviceConfig config_;
  std::vector<FrameEvent> events_;
  std::optional<sim::SimFrame> rendered_;  // the last frame rendered (its colour, then depth)
};

}  // namespace icgm

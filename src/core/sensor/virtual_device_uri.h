// The URI of the project's virtual OpenNI2 device (virtual_driver.cpp), which serves the frames
// of a TUM RGB-D folder or of a simulated scenario through OpenNI2 as a Kinect would:
//   icgm-virtual://tum?dir=/data/tum_fr1_xyz[&frames=100][&rate=1.0][&loop=1][&camera=tum.yaml]
//   icgm-virtual://sim?scenario=config/sim/crowded.yaml[&frames=100][&rate=1.0][&loop=1]
// dir: the TUM folder; scenario: a simulator YAML (config/sim/*.yaml; its camera gives the
// field of view); frames: the first N frames only (0 = all); rate: playback speed against the
// recording's stamps (device stamps keep the recording's spacing); loop: start over at the end;
// camera (tum only): a camera YAML (config/camera/*.yaml) for the field of view and image size.
// The driver also announces the device named by the environment variable
// ICGM_VIRTUAL_DEVICE (a URI as above), so that "the first device" finds it.
#pragma once

#include <string>

#include "core/common/status.h"

namespace icgm {

inline constexpr char kVirtualDeviceScheme[] = "icgm-virtual://";
inline constexpr char kVirtualDeviceEnv[] = "ICGM_VIRTUAL_DEVICE";
// Name of the device's thread that decodes the stored frames (the work a real camera does in
// its hardware), so that CPU measurements of a process can leave it out.
inline constexpr char kVirtualDeviceLoaderThread[] = "icgm_vdev_load";

struct VirtualDeviceConfig {
  std::string source;  // "tum" or "sim"
  std::string dir;       // tum
  std::string scenario;  // sim
  int max_frames = 0;  // 0: all
  double rate = 1.0;
  bool loop = false;
  std::string camera_yaml;  // "" = default 640x480 Kinect intrinsics
};

bool IsVirtualDeviceUri(const std::string& uri);
// Fails naming the offending part ("virtual device URI 'x': unknown parameter 'fps'").
Status ParseVirtualDeviceUri(const std::string& uri, VirtualDeviceConfig* out);

}  // namespace icgm

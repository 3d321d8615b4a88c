// A velocity command for a differential-drive base, in base_link (x forward, rotation about z
// counter-clockwise). Shared by the navigation and the simulator that executes it.
#pragma once

namespace icgm {

struct VelocityCommand {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

}  // namespace icgm

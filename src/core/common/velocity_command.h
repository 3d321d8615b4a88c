// Velocity command of a differential-drive base (base_link: x forward, z up), as the navigation
// stack produces it and the closed-loop simulator or a robot driver consumes it.
#pragma once

namespace icgm {

struct VelocityCommand {
  double linear_mps = 0.0;     // forward speed of base_link
  double angular_radps = 0.0;  // yaw rate, counter-clockwise positive
};

}  // namespace icgm

// Exact SE(3) exponential and logarithm (one-parameter subgroups). Unlike the decoupled
// LogSE3/ExpSE3 of core/common/pose.h, these satisfy Exp(s*xi) * Exp(t*xi) = Exp((s+t)*xi),
// which the semi-consensus correction (thesis eq. 6.4) relies on to split a pose difference into
// equal increments. Twist layout: (u_x, u_y, u_z, w_x, w_y, w_z) with w the rotation vector and
// u the translational velocity (translation = V(w) * u).
#pragma once

#include <Eigen/Core>

#include "core/common/pose.h"

namespace icgm {

// Rotation angle must stay below pi for Log to be the inverse of Exp.
Vec6 GeodesicLog(const Pose3& pose);
Pose3 GeodesicExp(const Vec6& twist);

}  // namespace icgm

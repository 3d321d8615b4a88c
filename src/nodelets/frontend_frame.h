// One synchronised RGB-D frame of the registration nodelet (features + depth messages) as the
// core's live front end takes it (core/slam/live_frontend.h), and the start of that front end
// with the first frame's camera.
#pragma once

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <icgm_slam/RobustFeatures.h>

#include "core/common/status.h"
#include "core/odometry/frontend_types.h"
#include "core/slam/live_frontend.h"
#include "nodelets/extrinsic_source.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

// The frame of `features` and `depth` (raw depth units / depth_scale = metres); error when a
// message cannot be converted. The depth is converted into frame->depth_m's buffer when it has
// the image's size (a buffer nothing else reads, from DepthBuffers), else into a new one.
Status ToLiveFrame(const icgm_slam::RobustFeatures& features, const sensor_msgs::Image& depth,
                   double depth_scale, LiveFrame* frame);

// Starts `live` for its oldest ready frame's camera (`info` through `camera`) once `extrinsic`
// knows the base -> camera transform; true when started. While the transform is missing the
// frames wait (all dropped once the wait bound passed); camera_info the reader refuses drops
// that frame (throttled error). Logs the start.
bool StartLiveFrontend(const FrontendOptions& options, ExtrinsicSource* extrinsic,
                       const CameraModelReader& camera, const sensor_msgs::CameraInfo& info,
                       LiveFrontend* live);

}  // namespace icgm::nodelets

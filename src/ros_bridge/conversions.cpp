#include "ros_bridge/conversions.h"

#include <algorithm>
#include <cmath>

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>

#include "core/dataset/depth_image.h"

namespace icgm::ros_bridge {

namespace enc = sensor_msgs::image_encodings;

ros::Time ToRos(Time t) {
  ros::Time r;
  r.fromNSec(static_cast<uint64_t>(t.nanoseconds() < 0 ? 0 : t.nanoseconds()));
  return r;
}

Time FromRos(const ros::Time& t) {
  return Time::FromNanoseconds(static_cast<int64_t>(t.toNSec()));
}

geometry_msgs::Point ToPointMsg(const Vec3& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

Vec3 FromPointMsg(const geometry_msgs::Point& msg) { return Vec3(msg.x, msg.y, msg.z); }

geometry_msgs::Pose ToPoseMsg(const Pose3& p) {
  geometry_msgs::Pose m;
  const Quat q(p.linear());
  m.position = ToPointMsg(p.translation());
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  m.orientation.w = q.w();
  return m;
}

Pose3 FromPoseMsg(const geometry_msgs::Pose& m) {
  return MakePose(Vec3(m.position.x, m.position.y, m.position.z),
                  Quat(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z));
}

geometry_msgs::Transform ToTransformMsg(const Pose3& p) {
  const geometry_msgs::Pose pm = ToPoseMsg(p);
  geometry_msgs::Transform t;
  t.translation.x = pm.position.x;
  t.translation.y = pm.position.y;
  t.translation.z = pm.position.z;
  t.rotation = pm.orientation;
  return t;
}

Pose3 FromTransformMsg(const geometry_msgs::Transform& t) {
  return MakePose(Vec3(t.translation.x, t.translation.y, t.translation.z),
                  Quat(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z));
}

sensor_msgs::CameraInfo ToCameraInfo(const CameraIntrinsics& k, const std::string& frame_id,
                                     Time t) {
  sensor_msgs::CameraInfo m;
  m.header.stamp = ToRos(t);
  m.header.frame_id = frame_id;
  m.width = static_cast<uint32_t>(k.width_px);
  m.height = static_cast<uint32_t>(k.height_px);
  m.distortion_model = "plumb_bob";
  m.D = {k.distortion_k1, k.distortion_k2, k.distortion_p1, k.distortion_p2, k.distortion_k3};
  m.K = {k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1};
  m.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.P = {k.fx_px, 0, k.cx_px, 0, 0, k.fy_px, k.cy_px, 0, 0, 0, 1, 0};
  return m;
}

Status FromCameraInfo(const sensor_msgs::CameraInfo& m, double depth_scale, CameraIntrinsics* out) {
  const double fx = m.K[0], fy = m.K[4], cx = m.K[2], cy = m.K[5];
  if (!(std::isfinite(fx) && std::isfinite(fy) && fx > 0 && fy > 0)) {
    return Status::Error("camera_info has no valid focal length (K[0]=" + std::to_string(fx) +
                         ", K[4]=" + std::to_string(fy) + "): camera not calibrated");
  }
  if (m.width == 0 || m.height == 0) return Status::Error("camera_info has zero image size");
  CameraIntrinsics k;
  k.fx_px = fx;
  k.fy_px = fy;
  k.cx_px = cx;
  k.cy_px = cy;
  k.width_px = static_cast<int>(m.width);
  k.height_px = static_cast<int>(m.height);
  k.depth_scale = depth_scale;
  // plumb_bob (and rational_polynomial's first five terms, which share the order) k1 k2 p1 p2 k3.
  const bool any_d = std::any_of(m.D.begin(), m.D.end(), [](double d) { return d != 0.0; });
  if (any_d) {
    if (m.distortion_model != "plumb_bob" && m.distortion_model != "rational_polynomial") {
      return Status::Error("camera_info distortion model '" + m.distortion_model +
                           "' not supported (plumb_bob expected)");
    }
    if (m.distortion_model == "rational_polynomial" &&
        std::any_of(m.D.begin() + std::min<size_t>(5, m.D.size()), m.D.end(),
                    [](double d) { return d != 0.0; })) {
      return Status::Error("camera_info rational_polynomial terms k4-k6 not supported");
    }
    double* d[5] = {&k.distortion_k1, &k.distortion_k2, &k.distortion_p1, &k.distortion_p2,
                    &k.distortion_k3};
    for (size_t i = 0; i < std::min<size_t>(5, m.D.size()); ++i) *d[i] = m.D[i];
  }
  *out = k;
  return Status::Ok();
}

sensor_msgs::Image ToImageMsg(const cv::Mat& image, const std::string& encoding,
                              const std::string& frame_id, Time t) {
  std_msgs::Header h;
  h.stamp = ToRos(t);
  h.frame_id = frame_id;
  sensor_msgs::Image msg;
  cv_bridge::CvImage(h, encoding, image).toImageMsg(msg);
  return msg;
}

namespace {
Status CheckShape(const sensor_msgs::Image& msg, int bytes_per_pixel) {
  if (msg.width == 0 || msg.height == 0) return Status::Error("image is empty (0 x 0)");
  if (msg.step < msg.width * static_cast<uint32_t>(bytes_per_pixel) ||
      msg.data.size() < static_cast<size_t>(msg.step) * msg.height) {
    return Status::Error("image data size " + std::to_string(msg.data.size()) +
                         " does not match " + std::to_string(msg.height) + " rows of step " +
                         std::to_string(msg.step));
  }
  return Status::Ok();
}
}  // namespace

Status ColorFromImageMsg(const sensor_msgs::Image& msg, cv::Mat* bgr) {
  const std::string& e = msg.encoding;
  int bpp = 0;
  if (e == enc::BGR8 || e == enc::RGB8) bpp = 3;
  else if (e == enc::BGRA8 || e == enc::RGBA8) bpp = 4;
  else if (e == enc::MONO8) bpp = 1;
  else return Status::Error("colour image has unsupported encoding '" + e +
                            "' (expected bgr8, rgb8, bgra8, rgba8 or mono8)");
  if (Status s = CheckShape(msg, bpp); !s.ok()) return s;
  try {
    *bgr = cv_bridge::toCvCopy(msg, enc::BGR8)->image;
  } catch (const cv_bridge::Exception& ex) {
    return Status::Error(std::string("colour conversion failed: ") + ex.what());
  }
  return Status::Ok();
}

Status ColorViewOfImageMsg(const sensor_msgs::Image& msg, cv::Mat* bgr) {
  if (msg.encoding != enc::BGR8) return ColorFromImageMsg(msg, bgr);
  if (Status s = CheckShape(msg, 3); !s.ok()) return s;
  // cv::Mat does not write through a view it is given; the caller treats it as read-only.
  *bgr = cv::Mat(static_cast<int>(msg.height), static_cast<int>(msg.width), CV_8UC3,
                 const_cast<uint8_t*>(msg.data.data()), msg.step);
  return Status::Ok();
}

Status DepthFromImageMsg(const sensor_msgs::Image& msg, double depth_scale_16u, cv::Mat* depth_m) {
  depth_m->release();  // a new buffer: the old one may be shared
  return DepthFromImageMsgInto(msg, depth_scale_16u, depth_m);
}

Status DepthFromImageMsgInto(const sensor_msgs::Image& msg, double depth_scale_16u,
                             cv::Mat* buffer) {
  const std::string& e = msg.encoding;
  const bool is16 = (e == enc::TYPE_16UC1 || e == enc::MONO16);
  const bool is32 = (e == enc::TYPE_32FC1);
  if (!is16 && !is32) {
    return Status::Error("depth image has unsupported encoding '" + e +
                         "' (expected 16UC1 in mm or 32FC1 in m)");
  }
  if (Status s = CheckShape(msg, is16 ? 2 : 4); !s.ok()) return s;
  cv_bridge::CvImageConstPtr cv;
  try {
    cv = cv_bridge::toCvShare(msg, nullptr);
  } catch (const cv_bridge::Exception& ex) {
    return Status::Error(std::string("depth conversion failed: ") + ex.what());
  }
  ToMetricDepth(cv->image, is16 ? depth_scale_16u : 1.0, buffer);
  return Status::Ok();
}

Status MonoFromImageMsg(const sensor_msgs::Image& msg, cv::Mat* mono) {
  if (msg.encoding != enc::MONO8) {
    return Status::Error("mask image has unsupported encoding '" + msg.encoding +
                         "' (expected mono8)");
  }
  if (Status s = CheckShape(msg, 1); !s.ok()) return s;
  *mono = cv_bridge::toCvCopy(msg, enc::MONO8)->image;
  return Status::Ok();
}

}  // namespace icgm::ros_bridge

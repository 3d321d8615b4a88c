#include "ros_bridge/conversions.h"
#include "ros_bridge/image_size.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <sensor_msgs/image_encodings.h>

#include "core/dataset/camera_options.h"

namespace icgm::ros_bridge {
namespace {

TEST(ConversionsTest, TimeRoundTrip) {
  const Time t = Time::FromNanoseconds(1305031102175304123LL);
  EXPECT_EQ(FromRos(ToRos(t)), t);
  EXPECT_EQ(ToRos(t).sec, 1305031102u);
  EXPECT_EQ(ToRos(t).nsec, 175304123u);
}

TEST(ConversionsTest, PointRoundTrip) {
  const Vec3 v(1.5, -2.25, 0.75);
  EXPECT_TRUE(FromPointMsg(ToPointMsg(v)).isApprox(v, 0.0));
}

TEST(ConversionsTest, PoseAndTransformRoundTrip) {
  const Pose3 p =
      MakePose({1.5, -2, 0.25}, Quat(Eigen::AngleAxisd(1.2, Vec3(1, 2, 3).normalized())));
  EXPECT_TRUE(FromPoseMsg(ToPoseMsg(p)).isApprox(p, 1e-12));
  EXPECT_TRUE(FromTransformMsg(ToTransformMsg(p)).isApprox(p, 1e-12));
}

TEST(ConversionsTest, CameraInfoRoundTripAndRejectsUncalibrated) {
  CameraIntrinsics k;
  k.fx_px = 517.3;
  k.fy_px = 516.5;
  k.cx_px = 318.6;
  k.cy_px = 255.3;
  k.depth_scale = 5000;
  const auto msg = ToCameraInfo(k, "cam", Time::FromSeconds(3));
  CameraIntrinsics back;
  ASSERT_TRUE(FromCameraInfo(msg, 5000, &back).ok());
  EXPECT_DOUBLE_EQ(back.fx_px, k.fx_px);
  EXPECT_DOUBLE_EQ(back.cy_px, k.cy_px);
  EXPECT_EQ(back.width_px, 640);
  EXPECT_FALSE(back.HasDistortion());
  // plumb_bob distortion travels in D both ways.
  k.distortion_k1 = 0.039903;
  k.distortion_k2 = -0.099343;
  k.distortion_p1 = -0.00073;
  k.distortion_p2 = -0.000144;
  k.distortion_k3 = 0.01;
  ASSERT_TRUE(FromCameraInfo(ToCameraInfo(k, "cam", Time::FromSeconds(3)), 5000, &back).ok());
  EXPECT_DOUBLE_EQ(back.distortion_k1, k.distortion_k1);
  EXPECT_DOUBLE_EQ(back.distortion_k2, k.distortion_k2);
  EXPECT_DOUBLE_EQ(back.distortion_p1, k.distortion_p1);
  EXPECT_DOUBLE_EQ(back.distortion_p2, k.distortion_p2);
  EXPECT_DOUBLE_EQ(back.distortion_k3, k.distortion_k3);
  // A model whose coefficients mean something else is refused, not misread.
  auto fisheye = ToCameraInfo(k, "cam", Time::FromSeconds(3));
  fisheye.distortion_model = "equidistant";
  EXPECT_FALSE(FromCameraInfo(fisheye, 5000, &back).ok());
  sensor_msgs::CameraInfo zero;
  zero.width = 640;
  zero.height = 480;
  const Status s = FromCameraInfo(zero, 1000, &back);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("focal"), std::string::npos);
}

TEST(ConversionsTest, DepthMillimetresAndMetresGiveTheSameMetricImage) {
  cv::Mat mm(4, 5, CV_16UC1, cv::Scalar(1500));
  mm.at<uint16_t>(1, 2) = 0;  // hole
  cv::Mat m(4, 5, CV_32FC1, cv::Scalar(1.5f));
  m.at<float>(1, 2) = std::nanf("");
  cv::Mat a, b;
  ASSERT_TRUE(DepthFromImageMsg(ToImageMsg(mm, "16UC1", "cam", Time()), 1000, &a).ok());
  ASSERT_TRUE(DepthFromImageMsg(ToImageMsg(m, "32FC1", "cam", Time()), 1000, &b).ok());
  ASSERT_EQ(a.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(a.at<float>(0, 0), 1.5f);
  EXPECT_FLOAT_EQ(b.at<float>(3, 4), 1.5f);
  EXPECT_TRUE(std::isnan(a.at<float>(1, 2)));
  EXPECT_TRUE(std::isnan(b.at<float>(1, 2)));
}

TEST(ConversionsTest, WrongEncodingsAndTruncatedDataAreRejected) {
  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::Mat out;
  const auto color = ToImageMsg(bgr, "bgr8", "cam", Time());
  EXPECT_FALSE(DepthFromImageMsg(color, 1000, &out).ok());
  auto truncated = color;
  truncated.data.resize(10);
  EXPECT_FALSE(ColorFromImageMsg(truncated, &out).ok());
  cv::Mat depth(4, 4, CV_16UC1, cv::Scalar(1));
  EXPECT_FALSE(ColorFromImageMsg(ToImageMsg(depth, "16UC1", "cam", Time()), &out).ok());
  ASSERT_TRUE(ColorFromImageMsg(color, &out).ok());
  EXPECT_EQ(out.at<cv::Vec3b>(2, 2), cv::Vec3b(1, 2, 3));
  auto rgb = ToImageMsg(bgr, "rgb8", "cam", Time());
  ASSERT_TRUE(ColorFromImageMsg(rgb, &out).ok());
  EXPECT_EQ(out.at<cv::Vec3b>(2, 2), cv::Vec3b(3, 2, 1));
}

// bgr8 is viewed in place (no copy), with the message's row step; other encodings are converted.
TEST(ConversionsTest, ColourViewSharesBgr8AndConvertsTheRest) {
  cv::Mat bgr(5, 7, CV_8UC3);
  cv::randu(bgr, 0, 255);
  auto msg = ToImageMsg(bgr, "bgr8", "cam", Time());
  msg.step += 3;  // padded rows
  std::vector<uint8_t> padded;
  for (int r = 0; r < bgr.rows; ++r) {
    padded.insert(padded.end(), bgr.ptr<uint8_t>(r), bgr.ptr<uint8_t>(r) + bgr.cols * 3);
    padded.insert(padded.end(), 3, 0);
  }
  msg.data = padded;
  cv::Mat view, copy;
  ASSERT_TRUE(ColorViewOfImageMsg(msg, &view).ok());
  ASSERT_TRUE(ColorFromImageMsg(msg, &copy).ok());
  EXPECT_EQ(view.data, msg.data.data());
  EXPECT_EQ(cv::norm(view, bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(copy, bgr, cv::NORM_INF), 0.0);
  const auto rgb = ToImageMsg(bgr, "rgb8", "cam", Time());
  ASSERT_TRUE(ColorViewOfImageMsg(rgb, &view).ok());
  EXPECT_NE(view.data, rgb.data.data());
  EXPECT_EQ(view.at<cv::Vec3b>(2, 3)[0], bgr.at<cv::Vec3b>(2, 3)[2]);  // data read as rgb
  auto truncated = msg;
  truncated.data.resize(10);
  EXPECT_FALSE(ColorViewOfImageMsg(truncated, &view).ok());
}

// The shipped TUM fr1 calibration (640x480) and images of its size or of another one.
CameraIntrinsics TumFr1() { return LoadCameraIntrinsics("config/camera/tum_fr1.yaml"); }

sensor_msgs::Image Image(int width_px, int height_px, int type, const std::string& encoding) {
  return ToImageMsg(cv::Mat(height_px, width_px, type, cv::Scalar(0)), encoding, "camera",
                    Time::FromNanoseconds(1));
}

TEST(ImageSizeTest, ImagesOfTheCalibratedSizeFit) {
  const CameraIntrinsics k = TumFr1();
  ASSERT_EQ(k.width_px, 640);
  ASSERT_EQ(k.height_px, 480);
  const sensor_msgs::CameraInfo info = ToCameraInfo(k, "camera", Time::FromNanoseconds(1));
  const sensor_msgs::Image color = Image(640, 480, CV_8UC3, "bgr8");
  const sensor_msgs::Image depth = Image(640, 480, CV_16UC1, "16UC1");
  EXPECT_TRUE(CheckImageSize(color, "/camera/rgb/image_color", k, "tum_fr1.yaml").ok());
  EXPECT_TRUE(CheckImageSize(color, "/camera/rgb/image_color", info, "/camera/rgb/camera_info"));
  EXPECT_TRUE(CheckImageSize(depth, "/camera/depth/image", info, "/camera/rgb/camera_info"));
}

TEST(ImageSizeTest, AnImageOfAnotherSizeIsRefusedNamingBothSizesAndTheTopic) {
  const CameraIntrinsics k = TumFr1();
  const sensor_msgs::CameraInfo info = ToCameraInfo(k, "camera", Time::FromNanoseconds(1));
  const Status half = CheckImageSize(Image(320, 240, CV_8UC3, "bgr8"), "/camera/rgb/image_color",
                                     info, "/camera/rgb/camera_info");
  ASSERT_FALSE(half.ok());
  EXPECT_EQ(half.reason(),
            "'/camera/rgb/camera_info' is calibrated for 640x480 images, "
            "'/camera/rgb/image_color' carries 320x240");
  // One side alone differing is refused as well.
  EXPECT_FALSE(CheckImageSize(Image(640, 360, CV_8UC1, "mono8"), "/image", k, "tum_fr1.yaml"));
  EXPECT_FALSE(CheckImageSize(Image(480, 480, CV_8UC1, "mono8"), "/image", k, "tum_fr1.yaml"));
}

TEST(ImageSizeTest, DepthOfAnotherSizeThanTheColourCameraIsRefused) {
  // Depth not registered to colour (the depth camera's own 320x240 stream) against the colour
  // camera's camera_info: its pixels are not the colour camera's.
  const sensor_msgs::CameraInfo info = ToCameraInfo(TumFr1(), "camera", Time::FromNanoseconds(1));
  const Status s = CheckImageSize(Image(320, 240, CV_16UC1, "16UC1"), "/camera/depth/image_raw",
                                  info, "/camera/rgb/camera_info");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("640x480"), std::string::npos) << s.reason();
  EXPECT_NE(s.reason().find("'/camera/depth/image_raw' carries 320x240"), std::string::npos)
      << s.reason();
}

}  // namespace
}  // namespace icgm::ros_bridge

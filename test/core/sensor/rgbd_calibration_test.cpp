// A driver's calibration from a camera YAML: the Kinect defaults carry the colour camera and the
// depth camera (software registration for a device without hardware registration, none for one
// with it); the TUM calibration only the colour camera; a broken file is a reason, not a throw.
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "core/sensor/rgbd_calibration.h"

namespace icgm {
namespace {

const std::string kDir = std::string(ICGM_SOURCE_DIR) + "/config/camera/";

TEST(RgbdCalibration, RegistersInSoftwareOnlyWhatNeedsIt) {
  std::vector<std::string> problems;
  const RgbdCalibration kinect = LoadRgbdCalibration(kDir + "kinect_default.yaml", &problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_TRUE(kinect.color.has_value());
  EXPECT_EQ(kinect.color->fx_px, 525.0);
  ASSERT_TRUE(kinect.depth_camera.has_value());
  EXPECT_NE(SoftwareRegistration(kinect, false, *kinect.color), nullptr);
  EXPECT_EQ(SoftwareRegistration(kinect, true, *kinect.color), nullptr);

  const RgbdCalibration tum = LoadRgbdCalibration(kDir + "tum_fr1.yaml", &problems);
  EXPECT_TRUE(problems.empty());
  EXPECT_TRUE(tum.color.has_value());
  EXPECT_FALSE(tum.depth_camera.has_value());
  EXPECT_EQ(SoftwareRegistration(tum, false, *tum.color), nullptr);
}

TEST(RgbdCalibration, ACalibrationOfAnotherImageSizeIsRefused) {
  std::vector<std::string> problems;
  const RgbdCalibration tum = LoadRgbdCalibration(kDir + "tum_fr1.yaml", &problems);
  ASSERT_TRUE(problems.empty());
  EXPECT_TRUE(CheckCalibratedSize(tum, 640, 480, "tum_fr1.yaml").ok());
  const Status s = CheckCalibratedSize(tum, 320, 240, "tum_fr1.yaml");
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("'tum_fr1.yaml' is calibrated for 640x480 images, the device "
                            "streams 320x240"),
            std::string::npos)
      << s.reason();
  EXPECT_TRUE(CheckCalibratedSize(RgbdCalibration(), 320, 240, "").ok());  // field of view
}

TEST(RgbdCalibration, BrokenFileGivesReasons) {
  const std::string path = testing::TempDir() + "icgm_rgbd_calibration_test.yaml";
  std::ofstream(path) << "camera: {fx_px: 525}\ndepth_camera: {fx_px: 580}\n";
  std::vector<std::string> problems;
  const RgbdCalibration c = LoadRgbdCalibration(path, &problems);
  std::remove(path.c_str());
  EXPECT_FALSE(c.depth_camera.has_value());
  ASSERT_FALSE(problems.empty());
  EXPECT_NE(problems.back().find("no software depth registration"), std::string::npos) << problems.back();
}

}  // namespace
}  // namespace icgm

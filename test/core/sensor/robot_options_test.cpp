#include "core/sensor/robot_options.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(RobotOptions, LoadsTheIws09WithItsKinectAt1300mm) {
  const RobotOptions o = LoadRobotOptions(std::string(ICGM_SOURCE_DIR) + "/config/robot/iws09.yaml");
  EXPECT_EQ(o.name, "iws09");
  EXPECT_DOUBLE_EQ(o.camera_z_m, 1.3);  // thesis ch. 6.1.3
  EXPECT_EQ(o.wheel_odom_topic, "/odom");
  EXPECT_EQ(o.cmd_vel_topic, "/cmd_vel");
}

TEST(RobotOptions, RejectsBadValuesNamingTheKey) {
  RobotOptions o;
  try {
    ReadOptions(OptionReader::FromString("robot: {max_linear_mps: 9}").Section("robot"), &o);
    FAIL() << "accepted 9 m/s";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("max_linear_mps"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadOptions(OptionReader::FromString("robot: {cmd_vel_topic: ''}").Section("robot"), &o),
               LoadError);
}

}  // namespace
}  // namespace icgm

// description/iws09.urdf passes check_urdf and mounts the camera where config/robot/iws09.yaml
// says (the launch files publish the URDF; the YAML is what a base controller reads).
#include <cstdlib>

#include <gtest/gtest.h>
#include <urdf/model.h>

#include "core/sensor/robot_options.h"

namespace icgm {
namespace {

const std::string kUrdf = std::string(ICGM_SOURCE_DIR) + "/description/iws09.urdf";

TEST(RobotDescription, PassesCheckUrdf) {
  EXPECT_EQ(std::system(("check_urdf " + kUrdf + " > /dev/null").c_str()), 0);
}

TEST(RobotDescription, CameraMountEqualsTheRobotConfig) {
  urdf::Model model;
  ASSERT_TRUE(model.initFile(kUrdf));
  const RobotOptions robot = LoadRobotOptions(std::string(ICGM_SOURCE_DIR) + "/config/robot/iws09.yaml");
  EXPECT_EQ(model.getRoot()->name, robot.base_frame);
  const auto link = model.getLink(robot.camera_frame);
  ASSERT_TRUE(link && link->parent_joint);
  EXPECT_EQ(link->parent_joint->parent_link_name, robot.base_frame);
  const urdf::Pose& p = link->parent_joint->parent_to_joint_origin_transform;
  EXPECT_NEAR(p.position.x, robot.camera_x_m, 1e-9);
  EXPECT_NEAR(p.position.y, robot.camera_y_m, 1e-9);
  EXPECT_NEAR(p.position.z, robot.camera_z_m, 1e-9);
  double roll, pitch, yaw;
  p.rotation.getRPY(roll, pitch, yaw);
  EXPECT_NEAR(roll * 180.0 / M_PI, robot.camera_roll_deg, 1e-6);
  EXPECT_NEAR(pitch * 180.0 / M_PI, robot.camera_pitch_deg, 1e-6);
  EXPECT_NEAR(yaw * 180.0 / M_PI, robot.camera_yaw_deg, 1e-6);
  ASSERT_TRUE(model.getLink("camera_rgb_optical_frame"));
}

}  // namespace
}  // namespace icgm

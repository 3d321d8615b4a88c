// The rostests' gtest node: one executable for every .test file, each selecting its own test
// case with --gtest_filter (the node name comes from the .test file's test-name).
#include <gtest/gtest.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "icgm_rostest");
  return RUN_ALL_TESTS();
}

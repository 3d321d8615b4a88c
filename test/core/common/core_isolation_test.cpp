// The core library must stay ROS-free: no ros/, *_msgs, tf2 or nodelet includes under src/core.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

TEST(CoreIsolationTest, NoRosIncludesInCore) {
  namespace fs = std::filesystem;
  const fs::path core = fs::path(ICGM_SOURCE_DIR) / "src" / "core";
  ASSERT_TRUE(fs::is_directory(core)) << core;
  const std::regex forbidden(
      R"(#\s*include\s*[<"](ros/|rosbag/|nodelet/|pluginlib/|tf2|tf2_ros/|cv_bridge/|image_transport/|message_filters/|pcl_conversions/|[a-z_]+_msgs/))");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(core)) {
    const auto ext = entry.path().extension();
    if (ext != ".h" && ext != ".cpp") continue;
    ++files;
    std::ifstream in(entry.path());
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      EXPECT_FALSE(std::regex_search(line, forbidden))
          << entry.path() << ":" << line_no << " includes ROS: " << line;
    }
  }
  EXPECT_GT(files, 5);
}

}  // namespace

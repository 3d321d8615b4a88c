// The core library must stay ROS-free: no ros/, *_msgs, tf2 or nodelet includes under src/core.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
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

// Every nodelet reads its private parameters through nodelets/nodelet_params.h's readers, which
// note them, and warns at the end of onInit about those it did not read (a misspelt name): no
// direct NodeHandle::param/getParam, and a WarnUnknownParams call in every nodelet.
TEST(CoreIsolationTest, NodeletsReadParametersThroughTheNotingReaders) {
  namespace fs = std::filesystem;
  const fs::path nodelets = fs::path(ICGM_SOURCE_DIR) / "src" / "nodelets";
  ASSERT_TRUE(fs::is_directory(nodelets)) << nodelets;
  const std::regex direct(R"((\.|->)(param|getParam|getParamCached)\s*(<[^>]*>)?\s*\()");
  int nodelet_files = 0;
  for (const auto& entry : fs::directory_iterator(nodelets)) {
    const auto ext = entry.path().extension();
    if (ext != ".h" && ext != ".cpp") continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (entry.path().filename() != "nodelet_params.h") {
      EXPECT_FALSE(std::regex_search(text, direct))
          << entry.path() << " reads a parameter directly: use Param/ParamInto/GetParam";
    }
    if (entry.path().filename().string().find("_nodelet.cpp") != std::string::npos) {
      ++nodelet_files;
      EXPECT_NE(text.find("WarnUnknownParams(getPrivateNodeHandle()"), std::string::npos)
          << entry.path() << " does not warn about unknown parameters";
    }
  }
  EXPECT_GE(nodelet_files, 8);
}

}  // namespace

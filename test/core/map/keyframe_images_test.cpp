// Keyframe images: subsampling keeps pixel identity and the camera model; the map store saves
// and loads them bit for bit and still loads maps of the schema before them.
#include <sqlite3.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/map/keyframe_images.h"
#include "core/map/map_store.h"

namespace icgm {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics k;
  k.fx_px = 525.0;
  k.fy_px = 520.0;
  k.cx_px = 319.5;
  k.cy_px = 239.5;
  return k;
}

// Depth of a tilted plane, colour from the pixel coordinates.
void MakeImages(cv::Mat* bgr, cv::Mat* depth) {
  *depth = cv::Mat(480, 640, CV_32FC1);
  *bgr = cv::Mat(480, 640, CV_8UC3);
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      depth->at<float>(y, x) = 1.0f + 0.004f * x + 0.001f * y;
      bgr->at<cv::Vec3b>(y, x) = cv::Vec3b(x % 256, y % 256, (x + y) % 256);
    }
  }
  depth->at<float>(2, 2) = std::numeric_limits<float>::quiet_NaN();
}

TEST(KeyframeImagesTest, SubsampleKeepsPixelsAndProjection) {
  cv::Mat bgr, depth;
  MakeImages(&bgr, &depth);
  const CameraIntrinsics full = Camera();
  const KeyframeImages images = DownsampleKeyframeImages(bgr, depth, full, 4);
  ASSERT_EQ(images.depth_mm.cols, 160);
  ASSERT_EQ(images.depth_mm.rows, 120);
  EXPECT_EQ(images.depth_mm.at<uint16_t>(0, 0), 0);  // full pixel (2, 2) had no depth
  for (const auto& [u, v] : {std::pair{5, 7}, std::pair{100, 80}, std::pair{159, 119}}) {
    const cv::Point2f px = images.FullPixel(u, v);
    EXPECT_NEAR(images.DepthM(u, v), depth.at<float>(px.y, px.x), 0.0006);
    EXPECT_EQ(images.bgr.at<cv::Vec3b>(v, u), bgr.at<cv::Vec3b>(px.y, px.x));
    // The stored camera lifts the stored pixel to the point the full camera sees at its pixel.
    const Eigen::Vector3d a = images.intrinsics.BackProject(u, v, 2.0);
    const Eigen::Vector3d b = full.BackProject(px.x, px.y, 2.0);
    EXPECT_LT((a - b).norm(), 1e-9);
  }
}

class KeyframeImagesStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("icgm_kf_images_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  HybridMap TwoKeyframes() {
    cv::Mat bgr, depth;
    MakeImages(&bgr, &depth);
    HybridMap map;
    for (int i = 0; i < 2; ++i) {
      Keyframe k;
      k.relative_pose.translation() = Eigen::Vector3d(0.1 * i, 0, 0);
      if (i == 0) k.images = DownsampleKeyframeImages(bgr, depth, Camera(), 4);
      int id = -1;
      EXPECT_TRUE(map.AddKeyframe(k, Mat6::Identity(), &id).ok());
    }
    return map;
  }
  std::filesystem::path dir_;
};

TEST_F(KeyframeImagesStoreTest, SaveLoadRoundTrip) {
  const HybridMap map = TwoKeyframes();
  const std::string path = (dir_ / "m.db").string();
  ASSERT_TRUE(SaveMap(map, path).ok());
  const HybridMap loaded = LoadMap(path);
  ASSERT_EQ(loaded.size(), 2);
  const KeyframeImages& a = map.keyframe(0).images;
  const KeyframeImages& b = loaded.keyframe(0).images;
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(cv::norm(a.depth_mm, b.depth_mm, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.bgr, b.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(b.downsample, 4);
  EXPECT_DOUBLE_EQ(a.intrinsics.cx_px, b.intrinsics.cx_px);
  EXPECT_DOUBLE_EQ(a.intrinsics.fy_px, b.intrinsics.fy_px);
  EXPECT_EQ(b.intrinsics.width_px, 160);
  EXPECT_TRUE(loaded.keyframe(1).images.empty());
}

TEST_F(KeyframeImagesStoreTest, SchemaOneMapsStillLoad) {
  const std::string path = (dir_ / "old.db").string();
  ASSERT_TRUE(SaveMap(TwoKeyframes(), path).ok());
  // Make it a version-1 file: no image table.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "DROP TABLE keyframe_images; PRAGMA user_version = 1; VACUUM;", nullptr,
               nullptr, nullptr);
  sqlite3_close(db);
  const HybridMap loaded = LoadMap(path);
  ASSERT_EQ(loaded.size(), 2);
  EXPECT_TRUE(loaded.keyframe(0).images.empty());
  EXPECT_NEAR(loaded.keyframe(1).global_pose.translation().x(), 0.1, 1e-12);
}

}  // namespace
}  // namespace icgm

#include "core/dataset/tum_dataset.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/common/status.h"
#include "temp_dir.h"

namespace icgm {
namespace {

using testing::TempDir;

CameraIntrinsics TumIntrinsics() {
  CameraIntrinsics k;
  k.fx_px = 517.3;
  k.fy_px = 516.5;
  k.cx_px = 318.6;
  k.cy_px = 255.3;
  k.depth_scale = 5000.0;
  return k;
}

// The small images the hand-written folders use.
CameraIntrinsics SmallIntrinsics() {
  CameraIntrinsics k = TumIntrinsics();
  k.width_px = 8;
  k.height_px = 6;
  return k;
}

// Writes a sequence folder: colour images of known colour, depth of known value.
void WriteImages(const TempDir& dir, const std::vector<std::string>& rgb_stamps,
                 const std::vector<std::string>& depth_stamps) {
  std::string rgb_txt = "# color images\n# timestamp filename\n";
  for (size_t i = 0; i < rgb_stamps.size(); ++i) {
    const std::string rel = "rgb/" + rgb_stamps[i] + ".png";
    rgb_txt += rgb_stamps[i] + " " + rel + "\n";
    std::filesystem::create_directories(dir.File("rgb"));
    cv::imwrite(dir.File(rel), cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 20 + i, 30)));
  }
  std::string depth_txt = "# depth maps\n";
  for (size_t i = 0; i < depth_stamps.size(); ++i) {
    const std::string rel = "depth/" + depth_stamps[i] + ".png";
    depth_txt += depth_stamps[i] + " " + rel + "\n";
    std::filesystem::create_directories(dir.File("depth"));
    cv::Mat depth(6, 8, CV_16UC1, cv::Scalar(static_cast<double>(5000 + 500 * i)));
    depth.at<uint16_t>(0, 0) = 0;
    cv::imwrite(dir.File(rel), depth);
  }
  dir.Write("rgb.txt", rgb_txt);
  dir.Write("depth.txt", depth_txt);
}

void ExpectOpenError(const std::string& dir, const std::string& reason_part) {
  try {
    TumDataset::Open(dir, SmallIntrinsics());
    ADD_FAILURE() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(reason_part), std::string::npos) << e.what();
  }
}

TEST(TumDatasetTest, AssociatesOneToOneByNearestStamp) {
  TempDir dir;
  // rgb 2.000 and 2.010 both have depth 2.008 as nearest; one-to-one matching gives 2.008 to
  // the closer 2.010 and 1.985 to 2.000. rgb 3.000 has no depth within 20 ms.
  WriteImages(dir, {"1.000", "1.100", "2.000", "2.010", "3.000"},
              {"1.005", "1.115", "1.985", "2.008", "3.030"});
  const TumDataset ds = TumDataset::Open(dir.path(), SmallIntrinsics(), 0.02);
  ASSERT_EQ(ds.size(), 4u);
  EXPECT_EQ(ds.unmatched_rgb(), 1u);
  const std::vector<std::pair<double, double>> expected = {
      {1.000, 1.005}, {1.100, 1.115}, {2.000, 1.985}, {2.010, 2.008}};
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(ds.frame(i).stamp, Time::FromSeconds(expected[i].first)) << i;
    EXPECT_EQ(ds.frame(i).depth_stamp, Time::FromSeconds(expected[i].second)) << i;
  }
  EXPECT_FALSE(ds.has_groundtruth());
  EXPECT_DOUBLE_EQ(ds.intrinsics().fx_px, 517.3);

  // A tighter window drops the 15 ms pairs.
  EXPECT_EQ(TumDataset::Open(dir.path(), SmallIntrinsics(), 0.01).size(), 2u);
}

TEST(TumDatasetTest, LoadsImagesAndMetricDepth) {
  TempDir dir;
  WriteImages(dir, {"5.0", "5.1"}, {"5.0", "5.1"});
  dir.Write("groundtruth.txt", "# gt\n5.05 1 2 3 0 0 0 1\n4.95 0 0 0 0 0 0 1\n");
  const TumDataset ds = TumDataset::Open(dir.path(), SmallIntrinsics());
  ASSERT_EQ(ds.size(), 2u);
  const cv::Mat bgr = ds.LoadBgr(1);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(2, 3), cv::Vec3b(10, 21, 30));
  const cv::Mat d = ds.LoadDepthM(1);
  ASSERT_EQ(d.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(d.at<float>(3, 3), 5500.0f / 5000.0f);
  EXPECT_TRUE(std::isnan(d.at<float>(0, 0)));
  ASSERT_TRUE(ds.has_groundtruth());
  ASSERT_EQ(ds.groundtruth().size(), 2u);
  EXPECT_TRUE(IsSortedByStamp(ds.groundtruth()));
}

TEST(TumDatasetTest, ClearErrors) {
  TempDir dir;
  ExpectOpenError(dir.File("nope"), "does not exist");
  ExpectOpenError(dir.path(), "no rgb.txt");
  WriteImages(dir, {"1.0"}, {"1.0"});
  dir.Write("rgb.txt", "1.0 rgb/1.0.png\n2.0\n");
  ExpectOpenError(dir.path(), "rgb.txt:2: expected 'timestamp path'");
  dir.Write("rgb.txt", "1.0x rgb/1.0.png\n");
  ExpectOpenError(dir.path(), "bad timestamp '1.0x'");
  dir.Write("rgb.txt", "1.0 rgb/missing.png\n");
  ExpectOpenError(dir.path(), "does not exist");
  dir.Write("rgb.txt", "1.0 rgb/1.0.png\n");
  std::filesystem::remove(dir.File("depth.txt"));
  ExpectOpenError(dir.path(), "no depth.txt");
  dir.Write("depth.txt", "1.0 depth/1.0.png\n");
  dir.Write("groundtruth.txt", "1.0 1 2 3\n");
  ExpectOpenError(dir.path(), "groundtruth.txt:1");
  std::filesystem::remove(dir.File("groundtruth.txt"));
  CameraIntrinsics bad = SmallIntrinsics();
  bad.fx_px = 0.0;
  EXPECT_THROW(TumDataset::Open(dir.path(), bad), LoadError);
  EXPECT_THROW(TumDataset::Open(dir.path(), SmallIntrinsics(), -1.0), LoadError);

  // Images of another size than the intrinsics are refused.
  const TumDataset wrong_size = TumDataset::Open(dir.path(), TumIntrinsics());
  EXPECT_THROW(wrong_size.LoadBgr(0), LoadError);
  EXPECT_THROW(wrong_size.LoadDepthM(0), LoadError);

  // Files that exist but are not images fail at load time with LoadError.
  const TumDataset ds = TumDataset::Open(dir.path(), SmallIntrinsics());
  ASSERT_EQ(ds.size(), 1u);
  EXPECT_NO_THROW(ds.LoadBgr(0));
  EXPECT_NO_THROW(ds.LoadDepthM(0));
  dir.Write("rgb/1.0.png", "not a png");
  dir.Write("depth/1.0.png", "not a png");
  EXPECT_THROW(ds.LoadBgr(0), LoadError);
  EXPECT_THROW(ds.LoadDepthM(0), LoadError);
  cv::imwrite(dir.File("depth/1.0.png"), cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_THROW(ds.LoadDepthM(0), LoadError);  // 8-bit colour is not a depth image
}

TEST(TumDatasetTest, RealFreiburg1Xyz) {
  const std::string dir = std::string(ICGM_SHARED_DATA_DIR) + "/tum_fr1_xyz";
  if (!std::filesystem::exists(dir + "/rgb.txt")) GTEST_SKIP() << "no data at " << dir;
  const TumDataset ds = TumDataset::Open(dir, TumIntrinsics(), 0.02);
  // fr1/xyz lists 798 colour and 798 depth images; associate.py-style matching within 20 ms
  // pairs 792 of them (checked with an independent script), a few lack a partner.
  EXPECT_GT(ds.size(), 790u);
  EXPECT_LE(ds.size(), 798u);
  EXPECT_EQ(ds.size() + ds.unmatched_rgb(), 798u);
  std::set<int64_t> depth_used;
  for (size_t i = 0; i < ds.size(); ++i) {
    EXPECT_LE(std::abs(DurationSeconds(ds.frame(i).stamp, ds.frame(i).depth_stamp)), 0.02);
    if (i > 0) {
      EXPECT_LT(ds.frame(i - 1).stamp, ds.frame(i).stamp);
    }
    EXPECT_TRUE(depth_used.insert(ds.frame(i).depth_stamp.nanoseconds()).second);
  }
  ASSERT_TRUE(ds.has_groundtruth());
  EXPECT_GT(ds.groundtruth().size(), 1000u);
  // Ground truth covers the colour frames (sampled at 100 Hz).
  EXPECT_TRUE(PoseAt(ds.groundtruth(), ds.frame(ds.size() / 2).stamp).has_value());

  const cv::Mat bgr = ds.LoadBgr(0);
  EXPECT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.cols, 640);
  EXPECT_EQ(bgr.rows, 480);
  const cv::Mat depth = ds.LoadDepthM(0);
  ASSERT_EQ(depth.type(), CV_32FC1);
  EXPECT_EQ(depth.size(), bgr.size());
  std::vector<float> valid;
  for (int r = 0; r < depth.rows; ++r) {
    for (int c = 0; c < depth.cols; ++c) {
      if (std::isfinite(depth.at<float>(r, c))) valid.push_back(depth.at<float>(r, c));
    }
  }
  // A desk scene seen by a Kinect: mostly valid, metres not millimetres.
  EXPECT_GT(valid.size(), depth.total() / 2);
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  EXPECT_GT(valid[valid.size() / 2], 0.4f);
  EXPECT_LT(valid[valid.size() / 2], 4.0f);
}

}  // namespace
}  // namespace icgm

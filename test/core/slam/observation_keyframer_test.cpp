#include "core/slam/observation_keyframer.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/slam/slam_system.h"

namespace icgm {
namespace {

// A frame of `n` keypoints on a grid, every other one robust, with binary descriptors.
TrackedFrame MakeFrame(Time stamp, int n, uint64_t seed) {
  TrackedFrame f;
  f.stamp = stamp;
  std::mt19937_64 rng(seed);
  f.features.descriptors.create(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) {
    f.features.keypoints.emplace_back(40.f + 20.f * (i % 25), 40.f + 20.f * (i / 25), 8.f);
    f.robust.push_back(i % 2 == 0);
    for (int b = 0; b < 32; ++b) f.features.descriptors.at<uint8_t>(i, b) = rng() & 0xff;
  }
  return f;
}

CameraIntrinsics Kinect() { return CameraIntrinsics{}; }

TEST(ObservationKeyframerTest, KeyframesFollowMotionAndCarryDepthPoints) {
  KeyframerOptions options;
  options.min_translation_m = 0.25;
  options.max_interval_frames = 1000;
  ObservationKeyframer keyframer(options);
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  std::vector<size_t> keyframe_frames;
  for (int i = 0; i < 10; ++i) {
    const Pose3 odom_camera = MakePose({0.1 * i, 0, 0}, Quat::Identity());
    auto kf = keyframer.Offer(MakeFrame(Time::FromSeconds(i), 100, i), depth, Kinect(), odom_camera);
    if (!kf) continue;
    keyframe_frames.push_back(kf->frame_index);
    ASSERT_EQ(kf->points_m.size(), 100u);
    // Back-projection of a keypoint at depth 2 m.
    const Vec3 expected = Kinect().BackProject(40.0, 40.0, 2.0);
    EXPECT_NEAR((kf->points_m[0] - expected).norm(), 0.0, 1e-5);
    EXPECT_EQ(kf->robust[0], 1);
    EXPECT_EQ(kf->robust[1], 0);
    if (keyframe_frames.size() > 1) {
      EXPECT_NEAR(kf->relative_pose.translation().x(), 0.3, 1e-9);
    }
  }
  // 0.1 m per frame and a 0.25 m threshold: frames 0, 3, 6, 9.
  EXPECT_EQ(keyframe_frames, (std::vector<size_t>{0, 3, 6, 9}));
}

TEST(ObservationKeyframerTest, AppliesTheCamerasDepthCorrection) {
  ObservationKeyframer keyframer(KeyframerOptions{});
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  CameraIntrinsics corrected = Kinect();
  corrected.depth_correction = 1.035;
  const auto kf =
      keyframer.Offer(MakeFrame(Time::FromSeconds(1), 100, 1), depth, corrected, Pose3::Identity());
  ASSERT_TRUE(kf.has_value());
  EXPECT_NEAR((kf->points_m[0] - corrected.BackProject(40.0, 40.0, 2.07)).norm(), 0.0, 1e-5);
  EXPECT_NEAR(kf->depth_m.at<float>(100, 100), 2.07f, 1e-5f);
  EXPECT_FLOAT_EQ(depth.at<float>(100, 100), 2.0f) << "the caller's image is not changed";
}

TEST(ObservationKeyframerTest, FramesWithoutDepthAreNotKeyframes) {
  ObservationKeyframer keyframer(KeyframerOptions{});
  const cv::Mat no_depth(480, 640, CV_32FC1, cv::Scalar(std::nanf("")));
  EXPECT_FALSE(keyframer.Offer(MakeFrame(Time::FromSeconds(1), 100, 1), no_depth, Kinect(),
                               Pose3::Identity()));
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  Pose3 bad = Pose3::Identity();
  bad.translation().x() = std::nan("");
  EXPECT_FALSE(keyframer.Offer(MakeFrame(Time::FromSeconds(2), 100, 2), depth, Kinect(), bad));
  EXPECT_TRUE(keyframer.Offer(MakeFrame(Time::FromSeconds(3), 100, 3), depth, Kinect(),
                              Pose3::Identity()));
}

TEST(ObservationKeyframerTest, BringsARollingShutterKeyframeToItsStampInstant) {
  // A camera sliding sideways at 0.6 m/s past a wall 2 m away, 30 frames/s; its rows are read
  // out over 30 ms with the stamp at the middle row, so a keypoint in row v was seen
  // tau(v) = -15 ms + v * 30 ms / 479 from the stamp, 0.6 * tau(v) m off to the side.
  CameraIntrinsics rolling = Kinect();
  rolling.readout_s = 0.03;
  rolling.first_row_offset_s = -0.015;
  KeyframerOptions options;
  options.min_translation_m = 0.01;  // every frame a keyframe
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  const auto stamp = [](int i) { return Time::FromNanoseconds(1'000'000'000LL + i * 33'333'333LL); };
  const auto pose = [&](int i) {
    return MakePose({0.6 * DurationSeconds(stamp(i), stamp(0)), 0, 0}, Quat::Identity());
  };
  for (const bool compensate : {true, false}) {
    options.compensate_sensor_timing = compensate;
    ObservationKeyframer keyframer(options);
    ASSERT_TRUE(keyframer.Offer(MakeFrame(stamp(0), 100, 1), depth, rolling, pose(0)));
    const TrackedFrame frame = MakeFrame(stamp(1), 100, 2);
    const auto kf = keyframer.Offer(frame, depth, rolling, pose(1));
    ASSERT_TRUE(kf.has_value());
    ASSERT_EQ(kf->points_m.size(), frame.features.size());
    double worst_m = 0.0;
    for (size_t k = 0; k < frame.features.size(); ++k) {
      const cv::Point2f px = frame.features.keypoints[k].pt;
      const double tau_s = -0.015 + px.y * 0.03 / 479.0;
      Vec3 truth = rolling.BackProject(px.x, px.y, 2.0);
      truth.x() += 0.6 * tau_s;
      ASSERT_TRUE(kf->points_m[k].allFinite()) << k;
      worst_m = std::max(worst_m, (kf->points_m[k] - truth).norm());
      if (compensate) {
        // The keypoint itself moved to where the camera at the stamp sees the point.
        EXPECT_NEAR(kf->features.keypoints[k].pt.x, rolling.Project(truth).x(), 0.01) << k;
      }
    }
    if (compensate) {
      EXPECT_LT(worst_m, 1e-4);
    } else {
      EXPECT_GT(worst_m, 0.005);  // rows 40-100 are 9-13 ms before the stamp
    }
  }
}

TEST(ObservationKeyframerTest, ExternalKeyframesBuildTheMapInOrder) {
  SlamOptions options;
  SlamSystem system(options, Kinect());
  KeyframerOptions kopt;
  kopt.min_translation_m = 0.2;
  ObservationKeyframer keyframer(kopt);
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  int added = 0;
  for (int i = 0; i < 12; ++i) {
    const Pose3 odom_camera = MakePose({0.1 * i, 0.02 * i, 0}, Quat::Identity());
    auto kf = keyframer.Offer(MakeFrame(Time::FromSeconds(1 + i), 100, 7 * i), depth, Kinect(),
                              odom_camera);
    if (!kf) continue;
    const SlamFrameResult r = system.AddKeyframe(*kf);
    ASSERT_TRUE(r.map_status.ok()) << r.map_status.reason();
    ++added;
    // Without loop closures the map follows the odometry exactly.
    EXPECT_TRUE(system.map().keyframe(r.keyframe_id).global_pose.isApprox(odom_camera, 1e-9));
  }
  EXPECT_EQ(system.map().size(), added);
  EXPECT_GE(added, 4);
  // A keyframe older than the last one is refused with a reason, and the map is unchanged.
  auto late = keyframer.Offer(MakeFrame(Time::FromSeconds(0.5), 100, 99), depth, Kinect(),
                              MakePose({5, 0, 0}, Quat::Identity()));
  ASSERT_TRUE(late.has_value());
  const SlamFrameResult r = system.AddKeyframe(*late);
  EXPECT_FALSE(r.map_status.ok());
  EXPECT_EQ(system.map().size(), added);
}

}  // namespace
}  // namespace icgm

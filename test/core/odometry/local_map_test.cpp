#include "core/odometry/local_map.h"

#include "core/odometry/map_hypothesis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace icgm {
namespace {

CameraIntrinsics TestCamera() {
  CameraIntrinsics k;
  k.fx_px = 540.0;
  k.fy_px = 540.0;
  k.cx_px = 320.0;
  k.cy_px = 240.0;
  k.width_px = 640;
  k.height_px = 480;
  return k;
}

// A room seen by two keyframes and a current frame with known poses: static points on walls
// 2.5-4.5 m away, each with a random 32-byte descriptor; the current frame observes them with
// 0.3 px noise and slightly perturbed descriptors.
struct Scene {
  CameraIntrinsics camera = TestCamera();
  Pose3 odom_kf1 = Pose3::Identity(), odom_kf2 = Pose3::Identity(), odom_cur = Pose3::Identity();
  std::vector<Vec3> odom_points;
  cv::Mat descriptors;  // one row per point
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat current_descriptors;
  std::vector<int> point_of_keypoint;
  cv::Mat depth;  // current frame's depth at its keypoints (elsewhere invalid)

  explicit Scene(int num_points, unsigned seed = 3) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), d(2.5, 4.5);
    std::normal_distribution<double> px_noise(0.0, 0.3);
    odom_kf2.translate(Vec3(0.05, 0.0, 0.01));
    odom_kf2.rotate(Eigen::AngleAxisd(0.04, Vec3::UnitY()));
    odom_cur.translate(Vec3(0.09, 0.01, 0.02));
    odom_cur.rotate(Eigen::AngleAxisd(0.07, Vec3::UnitY()) *
                    Eigen::AngleAxisd(0.01, Vec3::UnitX()));
    descriptors.create(num_points, 32, CV_8U);
    cv::randu(descriptors, 0, 256);
    current_descriptors = descriptors.clone();
    depth = cv::Mat(camera.height_px, camera.width_px, CV_32FC1, cv::Scalar(0.0f));
    const Pose3 cur_odom = odom_cur.inverse();
    for (int i = 0; i < num_points; ++i) {
      const double z = d(rng);
      const Vec3 p(u(rng) * 0.5 * z, u(rng) * 0.4 * z, z);
      odom_points.push_back(p);
      // A few bits differ in the current frame's descriptor.
      current_descriptors.at<uint8_t>(i, i % 32) ^= 0x5;
      const Vec3 pc = cur_odom * p;
      const Eigen::Vector2d px = camera.Project(pc);
      keypoints.emplace_back(static_cast<float>(px.x() + px_noise(rng)),
                             static_cast<float>(px.y() + px_noise(rng)), 7.0f);
      point_of_keypoint.push_back(i);
      const int r = cvRound(keypoints.back().pt.y), c = cvRound(keypoints.back().pt.x);
      if (r >= 0 && c >= 0 && r < depth.rows && c < depth.cols) {
        depth.at<float>(r, c) = static_cast<float>(pc.z());
      }
    }
  }

  // The map as the keyframes would give it: each point in its keyframe's camera frame.
  LocalMapPoints Map() const {
    LocalMapPoints map;
    const int half = static_cast<int>(odom_points.size()) / 2;
    for (const Pose3* kf : {&odom_kf1, &odom_kf2}) {
      std::vector<Vec3> camera_points;
      for (const Vec3& p : odom_points) camera_points.push_back(kf->inverse() * p);
      std::vector<uint8_t> use(odom_points.size(), 0);
      // The first keyframe holds the first half of the points, the second the rest, with an
      // overlap of ten (the same point seen by both).
      for (size_t i = 0; i < use.size(); ++i) {
        const int k = static_cast<int>(i);
        use[i] = kf == &odom_kf1 ? k < half + 10 : k >= half - 10;
      }
      AddKeyframePoints(descriptors, true, camera_points, use, *kf, &map);
    }
    return map;
  }
};

double TranslationErrorM(const Pose3& a, const Pose3& b) {
  return (a.translation() - b.translation()).norm();
}
double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  return Eigen::AngleAxisd((a.inverse() * b).rotation()).angle() * 180.0 / M_PI;
}

Pose3 Perturbed(const Pose3& p, double t_m, double r_rad) {
  Pose3 out = p;
  out.translate(Vec3(t_m, -0.5 * t_m, 0.3 * t_m));
  out.rotate(Eigen::AngleAxisd(r_rad, Vec3(0.2, 1.0, 0.1).normalized()));
  return out;
}

TEST(LocalMapTest, MapPointsOfSeveralKeyframesLandInTheOdomFrame) {
  const Scene scene(200);
  const LocalMapPoints map = scene.Map();
  ASSERT_EQ(map.size(), 220u);
  ASSERT_EQ(map.descriptors.rows, 220);
  // The second keyframe's first point (index half - 10 = 90) is the scene's point 90.
  EXPECT_LT((map.odom_points[110] - scene.odom_points[90]).norm(), 1e-9);
  EXPECT_LT((map.odom_points[0] - scene.odom_points[0]).norm(), 1e-9);
}

TEST(LocalMapTest, RefinesAPerturbedPoseToTheTruth) {
  const Scene scene(300);
  const LocalMapPoints map = scene.Map();
  const Pose3 start = Perturbed(scene.odom_cur, 0.008, 0.3 * M_PI / 180.0);
  ASSERT_GT(TranslationErrorM(start, scene.odom_cur), 0.007);
  LocalMapOptions options;
  options.keyframes = 2;
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  const LocalMapTrackResult r = TrackLocalMap(map, scene.keypoints, scene.current_descriptors,
                                              sigma, {}, scene.depth, start, scene.camera, options);
  ASSERT_TRUE(r.status.ok()) << r.status.reason();
  // Nearly every visible point matched once although the overlap is in the map twice.
  EXPECT_GT(r.matches, 250u);
  EXPECT_LE(r.matches, scene.keypoints.size());
  EXPECT_LT(TranslationErrorM(r.odom_camera, scene.odom_cur), 0.002);
  EXPECT_LT(RotationErrorDeg(r.odom_camera, scene.odom_cur), 0.03);
}

TEST(LocalMapTest, WalkersAndDynamicKeypointsDoNotPullThePose) {
  Scene scene(300);
  // A walker: a quarter of the points moved 3 px to the right in the current image (within
  // the search radius, same descriptors), their depth 1.2 m where the map says 2.5-4.5 m.
  std::vector<uint8_t> usable(scene.keypoints.size(), 1);
  for (size_t i = 0; i < scene.keypoints.size(); i += 4) {
    scene.keypoints[i].pt.x += 3.0f;
    const int r = cvRound(scene.keypoints[i].pt.y), c = cvRound(scene.keypoints[i].pt.x);
    if (r >= 0 && c >= 0 && r < scene.depth.rows && c < scene.depth.cols) {
      scene.depth.at<float>(r, c) = 1.2f;
    }
  }
  const LocalMapPoints map = scene.Map();
  const Pose3 start = Perturbed(scene.odom_cur, 0.005, 0.2 * M_PI / 180.0);
  LocalMapOptions options;
  options.keyframes = 2;
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  const LocalMapTrackResult with_depth =
      TrackLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, usable, scene.depth,
                    start, scene.camera, options);
  ASSERT_TRUE(with_depth.status.ok()) << with_depth.status.reason();
  EXPECT_LT(TranslationErrorM(with_depth.odom_camera, scene.odom_cur), 0.002);
  EXPECT_LT(RotationErrorDeg(with_depth.odom_camera, scene.odom_cur), 0.03);
  // Without the depth check the walker's points join the fit and pull it sideways.
  const LocalMapTrackResult without_depth =
      TrackLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, usable, cv::Mat(),
                    start, scene.camera, options);
  ASSERT_TRUE(without_depth.status.ok());
  EXPECT_GT(RotationErrorDeg(without_depth.odom_camera, scene.odom_cur),
            3.0 * RotationErrorDeg(with_depth.odom_camera, scene.odom_cur));
  // Keypoints flagged as dynamic are never matched: the walker's left out by the mask.
  for (size_t i = 0; i < usable.size(); i += 4) usable[i] = 0;
  const LocalMapTrackResult masked =
      TrackLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, usable, cv::Mat(),
                    start, scene.camera, options);
  ASSERT_TRUE(masked.status.ok());
  EXPECT_LE(masked.matches, 225u);
  EXPECT_LT(TranslationErrorM(masked.odom_camera, scene.odom_cur), 0.002);
}

TEST(LocalMapTest, FailuresLeaveTheStartAndSayWhy) {
  const Scene scene(300);
  const LocalMapPoints map = scene.Map();
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  LocalMapOptions options;
  options.keyframes = 2;
  // A start too far off: nothing lies within the search radius.
  const Pose3 far = Perturbed(scene.odom_cur, 0.0, 3.0 * M_PI / 180.0);
  const LocalMapTrackResult lost =
      TrackLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, {}, scene.depth, far,
                    scene.camera, options);
  EXPECT_FALSE(lost.status.ok());
  EXPECT_NE(lost.status.reason().find("matches"), std::string::npos) << lost.status.reason();
  EXPECT_TRUE(lost.odom_camera.isApprox(far));
  // A correction beyond the bound is rejected.
  options.max_correction_m = 0.002;
  const Pose3 start = Perturbed(scene.odom_cur, 0.008, 0.0);
  const LocalMapTrackResult bounded =
      TrackLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, {}, scene.depth, start,
                    scene.camera, options);
  EXPECT_FALSE(bounded.status.ok());
  EXPECT_NE(bounded.status.reason().find("bound"), std::string::npos) << bounded.status.reason();
  EXPECT_TRUE(bounded.odom_camera.isApprox(start));
  // An empty map.
  EXPECT_FALSE(TrackLocalMap(LocalMapPoints(), scene.keypoints, scene.current_descriptors, sigma,
                             {}, scene.depth, start, scene.camera, options)
                   .status.ok());
}

// The map hypothesis (map_hypothesis.h) on the same scene: located from the map alone. The
// scene's depth is known at the keypoints only, so the discontinuity test is off.
DepthPointOptions NoJumpTest() {
  DepthPointOptions depth;
  depth.max_depth_jump_ratio = 0.0;
  return depth;
}

TEST(MapHypothesisTest, LocatesTheFrameWithoutAStartPose) {
  const Scene scene(300);
  const LocalMapPoints map = scene.Map();
  // The viewing frame (the first keyframe) is 9 cm and 4 deg from the truth: far beyond what a
  // refinement from it would reach (LocalMapTest.FailuresLeaveTheStartAndSayWhy).
  ASSERT_GT(TranslationErrorM(scene.odom_kf1, scene.odom_cur), 0.09);
  ASSERT_GT(RotationErrorDeg(scene.odom_kf1, scene.odom_cur), 4.0);
  MapHypothesisOptions options;
  options.keyframes = 2;
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  const MapHypothesis h =
      LocateInLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, {}, scene.depth,
                       NoJumpTest(), scene.odom_kf1, scene.camera, options);
  ASSERT_TRUE(h.status.ok()) << h.status.reason();
  // The overlap's points are in the map twice: the ratio test drops their keypoints.
  EXPECT_GT(h.correspondences.size(), 250u);
  EXPECT_GT(h.inliers, 250u);
  EXPECT_LT(TranslationErrorM(h.odom_camera, scene.odom_cur), 0.003);
  EXPECT_LT(RotationErrorDeg(h.odom_camera, scene.odom_cur), 0.05);
}

TEST(MapHypothesisTest, WalkersDoNotWinAndSupportTellsThePoseApart) {
  Scene scene(300);
  // A walker: 40% of the keypoints moved 4 px to the right, at 1.2 m where the map says
  // 2.5-4.5 m (depth disagrees), and another 10% moved 4 px with their depth kept (a walker in
  // front of the wall it passes: only the reprojection tells).
  for (size_t i = 0; i < scene.keypoints.size(); ++i) {
    if (i % 10 >= 5) continue;
    scene.keypoints[i].pt.x += 4.0f;
    const int r = cvRound(scene.keypoints[i].pt.y), c = cvRound(scene.keypoints[i].pt.x);
    if (r < 0 || c < 0 || r >= scene.depth.rows || c >= scene.depth.cols) continue;
    const int r0 = r, c0 = cvRound(scene.keypoints[i].pt.x - 4.0f);
    const float z = c0 >= 0 && c0 < scene.depth.cols ? scene.depth.at<float>(r0, c0) : 3.0f;
    scene.depth.at<float>(r, c) = i % 10 == 4 ? z : 1.2f;
  }
  const LocalMapPoints map = scene.Map();
  MapHypothesisOptions options;
  options.keyframes = 2;
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  const MapHypothesis h =
      LocateInLocalMap(map, scene.keypoints, scene.current_descriptors, sigma, {}, scene.depth,
                       NoJumpTest(), scene.odom_kf1, scene.camera, options);
  ASSERT_TRUE(h.status.ok()) << h.status.reason();
  EXPECT_LT(TranslationErrorM(h.odom_camera, scene.odom_cur), 0.003);
  EXPECT_LT(RotationErrorDeg(h.odom_camera, scene.odom_cur), 0.05);
  EXPECT_LT(h.inliers, 170u);  // the room's half only
  // Support: the true pose explains the room's correspondences; a 2 cm sideways slide with the
  // pan that keeps the image centre in place (the motion a frame pair confuses) far fewer.
  const size_t at_truth = MapSupport(h.correspondences, scene.odom_cur, scene.camera, options);
  Pose3 slid = scene.odom_cur;
  slid.translate(Vec3(0.02, 0.0, 0.0));
  slid.rotate(Eigen::AngleAxisd(0.02 / 3.5, Vec3::UnitY()));
  const size_t at_slide = MapSupport(h.correspondences, slid, scene.camera, options);
  EXPECT_GT(at_truth, 130u);
  EXPECT_LT(at_slide, at_truth / 2) << at_slide << " vs " << at_truth;
}

TEST(MapHypothesisTest, FailuresSayWhy) {
  const Scene scene(300);
  const std::vector<double> sigma(scene.keypoints.size(), 1.0);
  MapHypothesisOptions options;
  options.keyframes = 2;
  const MapHypothesis empty =
      LocateInLocalMap(LocalMapPoints(), scene.keypoints, scene.current_descriptors, sigma, {},
                       scene.depth, NoJumpTest(), scene.odom_kf1, scene.camera, options);
  EXPECT_FALSE(empty.status.ok());
  EXPECT_NE(empty.status.reason().find("no map points"), std::string::npos);
  // Every keypoint masked as dynamic: nothing to match.
  const std::vector<uint8_t> none(scene.keypoints.size(), 0);
  const MapHypothesis masked =
      LocateInLocalMap(scene.Map(), scene.keypoints, scene.current_descriptors, sigma, none,
                       scene.depth, NoJumpTest(), scene.odom_kf1, scene.camera, options);
  EXPECT_FALSE(masked.status.ok());
  EXPECT_NE(masked.status.reason().find("map matches"), std::string::npos)
      << masked.status.reason();
  EXPECT_EQ(masked.correspondences.size(), 0u);
}

// Persistence: room points seen in place by keyframes over two seconds are kept; a walker's
// points, at a new place in every keyframe (0.3 m per 0.25 s: 1.2 m/s), are not.
// Keyframes 0.25 s apart of a room 3.5 m away and a walker at 1.5 m crossing it at 1.2 m/s;
// each keyframe sees every point with 1 cm of position noise.
std::vector<TimedMapPoints> RoomAndWalkerKeyframes(size_t count) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  const int room = 100, walker = 40;
  cv::Mat descriptors(room + walker, 32, CV_8U);
  cv::randu(descriptors, 0, 256);
  std::vector<Vec3> room_points, walker_points;
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < room; ++i) room_points.emplace_back(u(rng), u(rng), 3.5 + 0.3 * u(rng));
  for (int i = 0; i < walker; ++i) walker_points.emplace_back(0.2 * u(rng), u(rng), 1.5);
  std::vector<TimedMapPoints> keyframes(count);
  for (size_t k = 0; k < keyframes.size(); ++k) {
    keyframes[k].stamp_s = 0.25 * static_cast<double>(k);
    std::vector<Vec3> camera_points;
    for (const Vec3& p : room_points) camera_points.push_back(p + Vec3(noise(rng), noise(rng), 0));
    for (const Vec3& p : walker_points) {
      camera_points.push_back(p + Vec3(0.3 * static_cast<double>(k), noise(rng), 0));
    }
    AddKeyframePoints(descriptors, true, camera_points, {}, Pose3::Identity(),
                      &keyframes[k].points);
  }
  return keyframes;
}

TEST(MapHypothesisTest, PersistenceKeepsTheRoomAndDropsTheWalker) {
  const int room = 100, walker = 40;
  const std::vector<TimedMapPoints> keyframes = RoomAndWalkerKeyframes(9);
  const std::vector<TimedMapPoints> recent(keyframes.end() - 2, keyframes.end());
  MapHypothesisOptions options;
  // Off: every point of the two recent keyframes.
  EXPECT_EQ(PersistentPoints(recent, keyframes, options).size(), 2u * (room + walker));
  options.persistence_keyframes = 3;
  options.persistence_span_s = 1.0;
  options.persistence_radius_m = 0.1;
  const LocalMapPoints kept = PersistentPoints(recent, keyframes, options);
  size_t on_walker = 0;
  for (const Vec3& p : kept.odom_points) on_walker += p.z() < 2.0;
  EXPECT_EQ(on_walker, 0u);
  EXPECT_GE(kept.size(), 2u * room * 95 / 100);
  EXPECT_EQ(kept.descriptors.rows, static_cast<int>(kept.size()));
  // A span of 2.5 s asked of keyframes covering 2 s: no point qualifies.
  options.persistence_span_s = 2.5;
  EXPECT_EQ(PersistentPoints(recent, keyframes, options).size(), 0u);
}

bool SameMap(const LocalMapPoints& a, const LocalMapPoints& b) {
  return a.binary == b.binary && a.odom_points == b.odom_points &&
         a.descriptors.size() == b.descriptors.size() &&
         (a.descriptors.empty() || cv::norm(a.descriptors, b.descriptors, cv::NORM_INF) == 0);
}

// The cache over a sliding window gives PersistentPoints' map at every step, also when a
// keyframe's points change (new id) and when the options change.
TEST(MapHypothesisTest, PersistenceCacheEqualsTheFullRecomputation) {
  const std::vector<TimedMapPoints> all = RoomAndWalkerKeyframes(14);
  std::vector<std::shared_ptr<const TimedMapPoints>> points;
  std::vector<uint64_t> ids;
  for (size_t k = 0; k < all.size(); ++k) {
    points.push_back(std::make_shared<const TimedMapPoints>(all[k]));
    ids.push_back(k + 1);
  }
  // Every keyframe of the window must have seen a point: one changed observer changes the map.
  MapHypothesisOptions options;
  options.persistence_keyframes = 6;
  options.persistence_span_s = 0.5;
  options.persistence_radius_m = 0.1;
  PersistenceCache cache;
  size_t persistent_total = 0;
  for (size_t last = 5; last < all.size(); ++last) {
    // Observers: the six keyframes up to `last`; recent: the last two.
    const auto window = [&] {
      std::vector<TimedMapPoints> observers, recent;
      for (size_t k = last - 5; k <= last; ++k) {
        observers.push_back(*points[k]);
        if (k + 2 > last) recent.push_back(*points[k]);
      }
      return PersistentPoints(recent, observers, options);
    };
    if (last == 9) {
      // Keyframe 7's points move by 20 cm (e.g. its pose was adjusted): a new id.
      const LocalMapPoints unmoved = window();
      TimedMapPoints moved = *points[7];
      for (Vec3& p : moved.points.odom_points) p.x() += 0.2;
      points[7] = std::make_shared<const TimedMapPoints>(moved);
      ids[7] = 100;
      EXPECT_FALSE(SameMap(window(), unmoved));  // what a stale cache would give differs
    }
    if (last == 13) {
      const LocalMapPoints before = window();
      options.persistence_radius_m = 0.01;
      EXPECT_FALSE(SameMap(window(), before));
    }
    std::vector<PersistenceCache::Keyframe> observers, recent;
    for (size_t k = last - 5; k <= last; ++k) {
      observers.push_back({ids[k], points[k]});
      if (k + 2 > last) recent.push_back({ids[k], points[k]});
    }
    const LocalMapPoints expected = window();
    persistent_total += expected.size();
    EXPECT_TRUE(SameMap(cache.Points(recent, observers, options), expected))
        << "window ending at keyframe " << last;
    // Asked again with nothing changed.
    EXPECT_TRUE(SameMap(cache.Points(recent, observers, options), expected))
        << "window ending at keyframe " << last << ", again";
  }
  EXPECT_GT(persistent_total, 0u);
}

}  // namespace
}  // namespace icgm

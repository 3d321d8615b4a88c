#include "core/slam/slam_system.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "core/dataset/camera_options.h"
#include "core/eval/trajectory_evaluation.h"
#include "core/registration/depth_points.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "core/slam/keyframe_registration.h"
#include "core/slam/slam_runner.h"

namespace icgm {
namespace {

namespace fs = std::filesystem;

const std::string kDataDir = std::string(ICGM_SHARED_DATA_DIR) + "/tum_fr1_xyz";
constexpr size_t kFrames = 100;

// One SLAM run over the first kFrames frames of fr1/xyz, shared by the tests below.
class SlamSystemTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(kDataDir + "/rgb.txt")) return;
    const CameraIntrinsics camera =
        LoadCameraIntrinsics(std::string(ICGM_SOURCE_DIR) + "/config/camera/tum_fr1.yaml");
    dataset_ = std::make_shared<TumDataset>(TumDataset::Open(kDataDir, camera));
    system_ = std::make_unique<SlamSystem>(
        LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config"), dataset_->intrinsics());
    SlamRunOptions run;
    run.max_frames = kFrames;
    report_ =
        std::make_unique<SlamRunReport>(RunSlam(system_.get(), TumFrameSource(dataset_), run));
  }
  static void TearDownTestSuite() {
    system_.reset();
    report_.reset();
    dataset_.reset();
  }
  void SetUp() override {
    if (!system_) GTEST_SKIP() << "no TUM fr1/xyz data at " << kDataDir;
    dir_ = fs::temp_directory_path() /
           ("icgm_slam_system_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  static double AteRmse(const Trajectory& estimate) {
    TrajectoryEvaluation ev;
    const Status s =
        EvaluateTrajectory(dataset_->groundtruth(), estimate, TrajectoryEvalOptions(), &ev);
    EXPECT_TRUE(s.ok()) << s.reason();
    return s.ok() ? ev.ate.rmse : 1e9;
  }

  static std::shared_ptr<TumDataset> dataset_;
  static std::unique_ptr<SlamSystem> system_;
  static std::unique_ptr<SlamRunReport> report_;
  fs::path dir_;
};

std::shared_ptr<TumDataset> SlamSystemTest::dataset_;
std::unique_ptr<SlamSystem> SlamSystemTest::system_;
std::unique_ptr<SlamRunReport> SlamSystemTest::report_;

TEST_F(SlamSystemTest, MapKeyframesFollowGroundTruth) {
  EXPECT_EQ(report_->frames, kFrames);
  EXPECT_TRUE(report_->input_error.empty()) << report_->input_error;
  const HybridMap& map = system_->map();
  ASSERT_GE(map.size(), 3);
  EXPECT_EQ(static_cast<size_t>(map.size()), report_->map_keyframes);
  // Metric models hold ICGM features with 3-D points only.
  size_t features = 0;
  for (const Keyframe& kf : map.keyframes()) {
    features += kf.keypoints.size();
    for (const Vec3& p : kf.points_m) ASSERT_TRUE(p.allFinite());
  }
  EXPECT_GE(features, 50u * map.size());
  // fr1/xyz moves ~0.2 m in the first 100 frames; the keyframes and every frame must stay
  // within a few centimetres of the ground truth (after the benchmark's rigid alignment).
  EXPECT_LT(AteRmse(system_->KeyframeTrajectory()), 0.04);
  const Trajectory frames = system_->MapTrajectory();
  EXPECT_EQ(frames.size(), kFrames);
  EXPECT_LT(AteRmse(frames), 0.04);
}

TEST_F(SlamSystemTest, MapFromOdomComposesTheLatestFrame) {
  const Trajectory map_traj = system_->MapTrajectory();
  const Trajectory odom_traj = system_->OdomTrajectory();
  ASSERT_EQ(map_traj.size(), odom_traj.size());
  const Pose3 predicted = system_->MapFromOdom() * odom_traj.back().pose;
  EXPECT_TRUE(predicted.isApprox(map_traj.back().pose, 1e-9));
}

TEST_F(SlamSystemTest, SaveLoadRoundTripsTheMap) {
  ASSERT_TRUE(system_->Save(Path("map.db")).ok());
  SlamSystem other(system_->options(), dataset_->intrinsics());
  ASSERT_TRUE(other.Load(Path("map.db"), false).ok());
  const HybridMap& a = system_->map();
  const HybridMap& b = other.map();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.links().size(), b.links().size());
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a.keyframe(i).global_pose.isApprox(b.keyframe(i).global_pose, 1e-12));
    EXPECT_EQ(a.keyframe(i).keypoints.size(), b.keyframe(i).keypoints.size());
    EXPECT_EQ(cv::norm(a.keyframe(i).descriptors, b.keyframe(i).descriptors, cv::NORM_HAMMING), 0);
  }
  // Merging it into a running system appends a session and keeps the existing map.
  SlamSystem merged(system_->options(), dataset_->intrinsics());
  ASSERT_TRUE(merged.Load(Path("map.db"), false).ok());
  ASSERT_TRUE(merged.Load(Path("map.db"), true).ok());
  EXPECT_EQ(merged.map().size(), 2 * a.size());
  EXPECT_EQ(merged.map().sessions().size(), 2 * a.sessions().size());
  for (int i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(merged.map().keyframe(i).global_pose.isApprox(a.keyframe(i).global_pose, 1e-12));
  }
}

TEST_F(SlamSystemTest, BadInputNeverLosesTheMap) {
  ASSERT_TRUE(system_->Save(Path("map.db")).ok());
  SlamSystem s(system_->options(), dataset_->intrinsics());
  ASSERT_TRUE(s.Load(Path("map.db"), false).ok());
  const int size = s.map().size();
  // A missing and a foreign file are refused; the map stays.
  EXPECT_FALSE(s.Load(Path("missing.db"), false).ok());
  std::ofstream(Path("junk.db")) << "not a map";
  EXPECT_FALSE(s.Load(Path("junk.db"), true).ok());
  EXPECT_EQ(s.map().size(), size);
  // Empty, wrongly typed and out-of-order frames do not throw and add nothing broken.
  const Time t0 = dataset_->frame(0).stamp;
  s.ProcessFrame(t0, cv::Mat(), cv::Mat());
  s.ProcessFrame(Time::FromNanoseconds(t0.nanoseconds() + 1000), dataset_->LoadBgr(0),
                 cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
  s.ProcessFrame(t0, dataset_->LoadBgr(1), dataset_->LoadDepthM(1));
  EXPECT_GE(s.map().size(), size);
  for (int i = 0; i < size; ++i) {
    EXPECT_TRUE(s.map().keyframe(i).global_pose.isApprox(system_->map().keyframe(i).global_pose));
  }
  EXPECT_TRUE(s.map().Validate().ok());
  // Saving onto a directory fails and the saved map is still loadable.
  EXPECT_FALSE(s.Save(dir_.string()).ok());
  EXPECT_TRUE(s.Load(Path("map.db"), false).ok());
}

TEST_F(SlamSystemTest, NewSessionContinuesTheTrajectoryAndQueriesTheFirst) {
  SlamSystem s(system_->options(), dataset_->intrinsics());
  const KeyframeRegistration registration(system_->options().keyframe_registration,
                                          dataset_->intrinsics());
  int calls = 0;
  s.SetRegisterFn([&](const Keyframe& query, const Keyframe& candidate) {
    ++calls;
    return registration.Register(query, candidate);
  });
  SlamRunOptions run;
  run.max_frames = 40;
  const SlamFrameSource source = TumFrameSource(dataset_);
  RunSlam(&s, source, run);
  const int first_session_size = s.map().size();
  ASSERT_GE(first_session_size, 2);
  const Pose3 before = s.MapTrajectory().back().pose;
  s.StartSession();
  RunSlam(&s, source, run);  // the next 40 frames of the same source
  ASSERT_EQ(s.map().sessions().size(), 2u);
  ASSERT_GT(s.map().size(), first_session_size);
  EXPECT_EQ(s.map().keyframe(first_session_size).session_id, 1);
  // The second session starts where the first one left off: no jump between two frames.
  const Trajectory traj = s.MapTrajectory();
  ASSERT_EQ(traj.size(), 80u);
  EXPECT_TRUE(traj[39].pose.isApprox(before, 1e-9));
  EXPECT_LT(TranslationNorm(Between(traj[39].pose, traj[40].pose)), 0.05);
  // Keyframes of the second session looked for loop closures in the first one.
  EXPECT_GT(calls, 0);
}

// The wheels' motion between consecutive map keyframes becomes a wheel-odometry link beside each
// visual step, moved into the camera frame with the base-to-camera extrinsic.
TEST(SlamSystemWheelLinksTest, VisualStepsGetAWheelLinkInTheCameraFrame) {
  const sim::Simulator sim(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
  const size_t last = std::min<size_t>(sim.size(), 50);
  SlamOptions options = LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config");
  options.frontend.fusion.base_to_camera = sim.T_base_camera();
  ASSERT_TRUE(options.map.map.wheel_links);
  for (const bool wheels : {true, false}) {
    SlamSystem system(options, sim.intrinsics());
    std::map<int64_t, size_t> frame_of_stamp;
    for (size_t i = 0; i < last; ++i) {
      if (wheels) {
        ASSERT_TRUE(system.AddWheelOdometry(sim.stamp(i), sim.odometry(i).T_odom_base));
      }
      const sim::SimFrame f = sim.Render(i);
      frame_of_stamp[f.stamp.nanoseconds()] = i;
      system.ProcessFrame(f.stamp, f.bgr, f.depth_m);
    }
    const HybridMap& map = system.map();
    ASSERT_GE(map.size(), 3);
    int visual_steps = 0, wheel_links = 0;
    for (const Keyframe& kf : map.keyframes()) {
      visual_steps += kf.previous_id >= 0 && kf.relative_source == RelativePoseSource::kVisual;
    }
    for (const Link& l : map.links()) {
      if (l.type != LinkType::kWheelOdometry) continue;
      ++wheel_links;
      const size_t from = frame_of_stamp.at(map.keyframe(l.from_id).stamp.nanoseconds());
      const size_t to = frame_of_stamp.at(map.keyframe(l.to_id).stamp.nanoseconds());
      const Pose3 truth = Between(sim.T_world_camera(from), sim.T_world_camera(to));
      EXPECT_LT(TranslationNorm(Between(truth, l.relative_pose)),
                0.05 * TranslationNorm(truth) + 0.005)
          << "link " << l.from_id << " -> " << l.to_id;
      EXPECT_LT(RotationAngleRad(Between(truth, l.relative_pose)), 0.01);
    }
    EXPECT_EQ(wheel_links, wheels ? visual_steps : 0);
    if (wheels) {
      EXPECT_GT(visual_steps, 0);
    }
  }
}

// map_features.source = tracker (the thesis profile, 6.1.3.1): each keyframe enters the map one
// frame late with the double-directional ICGM set (S = 3) of its frame, the same set a tracker
// run on its own over the images gives; no keyframe is lost (the last one comes with Flush).
TEST(SlamSystemMapFeaturesTest, TrackerSourceGivesTheDoubleDirectionalSet) {
  const sim::Simulator sim(
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/static_short.yaml"));
  const size_t frames = std::min<size_t>(sim.size(), 40);
  SlamOptions options = LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config");
  options.frontend.fusion.base_to_camera = sim.T_base_camera();
  ASSERT_EQ(options.map_features.source, MapFeatureSource::kReferenceKeyframe);
  options.map_features.tracker.mode = TrackerMode::kDouble;
  options.map_features.tracker.window_size = 3;

  // Robust keypoints with a 3-D point of each frame by a tracker of its own (frame t comes
  // out with t+1).
  RobustFeatureTracker tracker(options.map_features.tracker);
  std::map<int64_t, std::multiset<std::pair<float, float>>> robust_at;
  std::map<int64_t, cv::Mat> depth_at;
  const auto keep = [&](const std::optional<TrackedFrame>& t) {
    if (!t) return;
    std::vector<cv::Point2f> pixels;
    for (const cv::KeyPoint& k : t->features.keypoints) pixels.push_back(k.pt);
    std::vector<Vec3> points;
    std::vector<uint8_t> valid;
    KeypointsToPoints(pixels, CorrectedDepth(depth_at.at(t->stamp.nanoseconds()), sim.intrinsics()),
                      sim.intrinsics(), options.frontend.registration.depth, &points, &valid);
    auto& set = robust_at[t->stamp.nanoseconds()];
    for (size_t i = 0; i < t->features.size(); ++i) {
      if (t->robust[i] && valid[i]) set.emplace(pixels[i].x, pixels[i].y);
    }
  };
  std::vector<sim::SimFrame> rendered;
  for (size_t i = 0; i < frames; ++i) {
    rendered.push_back(sim.Render(i));
    depth_at[rendered.back().stamp.nanoseconds()] = rendered.back().depth_m;
    keep(tracker.AddImage(rendered.back().stamp, rendered.back().bgr));
  }
  keep(tracker.Flush());

  std::map<MapFeatureSource, std::unique_ptr<SlamSystem>> systems;
  for (const MapFeatureSource source :
       {MapFeatureSource::kReferenceKeyframe, MapFeatureSource::kTracker}) {
    options.map_features.source = source;
    auto system = std::make_unique<SlamSystem>(options, sim.intrinsics());
    size_t keyframe_results = 0;
    for (size_t i = 0; i < frames; ++i) {
      ASSERT_TRUE(system->AddWheelOdometry(sim.stamp(i), sim.odometry(i).T_odom_base));
      const sim::SimFrame& f = rendered[i];
      const SlamFrameResult r = system->ProcessFrame(f.stamp, f.bgr, f.depth_m);
      keyframe_results += r.keyframe;
      if (source == MapFeatureSource::kTracker && r.keyframe_id >= 0) {
        EXPECT_LT(system->map().keyframe(r.keyframe_id).stamp, f.stamp)
            << "a held keyframe enters with the next frame";
      }
    }
    if (const auto last = system->Flush()) keyframe_results += last->keyframe;
    EXPECT_EQ(static_cast<int>(keyframe_results), system->map().size());
    EXPECT_EQ(system->MapTrajectory().size(), frames);
    systems[source] = std::move(system);
  }
  const HybridMap& ours = systems[MapFeatureSource::kReferenceKeyframe]->map();
  const HybridMap& thesis = systems[MapFeatureSource::kTracker]->map();
  ASSERT_GE(ours.size(), 3);
  ASSERT_EQ(thesis.size(), ours.size());
  int differing = 0;
  for (int k = 0; k < thesis.size(); ++k) {
    const Keyframe& kf = thesis.keyframe(k);
    EXPECT_EQ(kf.stamp, ours.keyframe(k).stamp);
    const auto& robust = robust_at.at(kf.stamp.nanoseconds());
    ASSERT_FALSE(robust.empty());
    // Exactly the tracker's set, less the keypoints without depth (keypoints at one pixel,
    // e.g. of two pyramid levels, count once each).
    for (const cv::KeyPoint& p : kf.keypoints) {
      EXPECT_TRUE(robust.count({p.pt.x, p.pt.y})) << "keyframe " << k << " at " << p.pt;
    }
    EXPECT_EQ(kf.keypoints.size(), robust.size()) << "keyframe " << k;
    differing += kf.keypoints.size() != ours.keyframe(k).keypoints.size();
  }
  EXPECT_GT(differing, 0);
}

}  // namespace
}  // namespace icgm

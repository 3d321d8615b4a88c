#include "core/nav/goal_session.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/map/map_store.h"
#include "synthetic_depth.h"
#include "unicycle.h"

namespace icgm {
namespace {

namespace fs = std::filesystem;
constexpr double kDt = 0.1;

Time At(double s) { return Time::FromSeconds(1000.0 + s); }

// A learned map of 16 keyframes 0.3 m apart along x (camera poses, base -> camera = mount),
// saved to a file of its own.
std::string SaveStraightMap(const std::string& name) {
  HybridMap map;
  int id = -1;
  Pose3 prev = Pose3::Identity();
  for (int i = 0; i <= 15; ++i) {
    const Pose3 cam = ToPose3(Pose2D{0.3 * i, 0.0, 0.0}) * test::MountPose();
    Keyframe kf;
    kf.relative_pose = i == 0 ? cam : Between(prev, cam);
    prev = cam;
    EXPECT_TRUE(map.AddKeyframe(kf, Mat6::Identity(), &id));
  }
  const std::string path = (fs::temp_directory_path() / name).string();
  EXPECT_TRUE(SaveMap(map, path).ok());
  return path;
}

GoalCycleInputs Inputs(double t, const std::optional<Pose2D>& pose, const Eigen::Vector2d& goal) {
  GoalCycleInputs in;
  in.now = At(t);
  in.dt_s = kDt;
  in.wall_s = t;
  if (pose) in.T_map_base = ToPose3(*pose);
  in.pose_error = "no map -> base_link on tf";
  in.goal_status = Status::Ok();
  in.goal_m = goal;
  in.T_base_camera = test::MountPose();
  return in;
}

TEST(GoalSessionTest, WithoutAMapEveryGoalIsAbortedWithTheReason) {
  GoalSession session;
  EXPECT_FALSE(session.Accept(0.0).ok());
  const Status empty = session.LoadMap("");
  EXPECT_FALSE(empty.ok());
  const std::string missing = (fs::temp_directory_path() / "goal_session_missing.db").string();
  fs::remove(missing);
  EXPECT_FALSE(session.LoadMap(missing).ok());
  const std::string corrupt = (fs::temp_directory_path() / "goal_session_corrupt.db").string();
  std::ofstream(corrupt) << "not a map at all";
  const Status bad = session.LoadMap(corrupt);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.reason().rfind("no map: ", 0), 0u) << bad.reason();
  const Status goal = session.Accept(1.0);
  ASSERT_FALSE(goal.ok());
  EXPECT_EQ(goal.reason(), bad.reason());
  EXPECT_FALSE(session.active());
  EXPECT_EQ(session.Cycle(Inputs(1.0, Pose2D{}, {3, 0})).result, GoalCycleResult::kIdle);
  fs::remove(corrupt);
}

TEST(GoalSessionTest, WaitsForThePoseThenAbortsWithWhatIsMissing) {
  GoalSession session(NavigationOptions(), /*pose_wait_s=*/2.0);
  ASSERT_TRUE(session.LoadMap(SaveStraightMap("goal_session_wait.db")).ok());
  ASSERT_TRUE(session.Accept(10.0).ok());
  GoalCycleInputs in = Inputs(11.0, std::nullopt, {3, 0});
  GoalCycle c = session.Cycle(in);
  EXPECT_EQ(c.result, GoalCycleResult::kWaiting);
  EXPECT_EQ(c.text, in.pose_error);
  in = Inputs(11.5, Pose2D{}, {3, 0});
  in.T_base_camera.reset();
  c = session.Cycle(in);
  EXPECT_EQ(c.result, GoalCycleResult::kWaiting);
  EXPECT_EQ(c.text, in.extrinsic_error);
  in.wall_s = 12.5;  // more than 2 s after the goal came
  c = session.Cycle(in);
  EXPECT_EQ(c.result, GoalCycleResult::kAborted);
  EXPECT_EQ(c.text, in.extrinsic_error);
  EXPECT_EQ(c.command.linear_mps, 0.0);
  EXPECT_FALSE(session.active());
}

TEST(GoalSessionTest, DrivesToTheGoalAndSucceeds) {
  GoalSession session;
  ASSERT_TRUE(session.LoadMap(SaveStraightMap("goal_session_drive.db")).ok());
  EXPECT_EQ(session.map().size(), 16);
  ASSERT_TRUE(session.Accept(0.0).ok());
  const Eigen::Vector2d goal(3.0, 0.1);
  const CameraIntrinsics k = test::SmallCamera();
  Pose2D pose{0.02, -0.03, 0.05};
  GoalCycle c;
  bool started = false, moved = false;
  for (double t = 0.0; t < 40.0; t += kDt) {
    session.UpdatePose(At(t), ToPose3(pose), t == 0.0);
    ASSERT_TRUE(session.UpdateDepth(At(t), test::RenderDepth(k, ToPose3(pose) * test::MountPose(),
                                                             {}),
                                    k, test::MountPose()));
    GoalCycleInputs in = Inputs(t, pose, goal);
    in.goal_yaw_rad = -0.8;  // the goal's orientation: turned to at the end
    c = session.Cycle(in);
    started |= c.result == GoalCycleResult::kStarted;
    moved |= c.result == GoalCycleResult::kDriving && c.command.linear_mps > 0.1;
    if (c.result == GoalCycleResult::kSucceeded || c.result == GoalCycleResult::kAborted) break;
    pose = test::Drive(pose, c.command, kDt);
  }
  EXPECT_TRUE(started);
  EXPECT_TRUE(moved);
  ASSERT_EQ(c.result, GoalCycleResult::kSucceeded) << c.text;
  EXPECT_NE(c.text.find("reached"), std::string::npos) << c.text;
  EXPECT_NE(c.text.find("deg from its yaw"), std::string::npos) << c.text;
  EXPECT_LT((pose.position() - goal).norm(), NavigationOptions().navigator.goal_tolerance_m);
  EXPECT_LE(std::abs(WrapAngleRad(pose.yaw_rad + 0.8)),
            NavigationOptions().navigator.goal_yaw_tolerance_rad);
  EXPECT_EQ(c.command.linear_mps, 0.0);
  EXPECT_EQ(session.Cycle(Inputs(50.0, pose, goal)).result, GoalCycleResult::kIdle);
}

TEST(GoalSessionTest, GoalOffTheMapIsAbortedAndCancelStops) {
  GoalSession session;
  ASSERT_TRUE(session.LoadMap(SaveStraightMap("goal_session_off.db")).ok());
  ASSERT_TRUE(session.Accept(0.0).ok());
  const CameraIntrinsics k = test::SmallCamera();
  session.UpdatePose(At(0), Pose3::Identity(), true);
  ASSERT_TRUE(session.UpdateDepth(At(0), test::RenderDepth(k, test::MountPose(), {}), k,
                                  test::MountPose()));
  GoalCycle c = session.Cycle(Inputs(0.0, Pose2D{}, {2.0, 5.0}));
  EXPECT_EQ(c.result, GoalCycleResult::kAborted);
  EXPECT_NE(c.text.find("off the map"), std::string::npos) << c.text;

  ASSERT_TRUE(session.Accept(1.0).ok());
  EXPECT_EQ(session.Cycle(Inputs(0.1, Pose2D{}, {4.0, 0.0})).result, GoalCycleResult::kStarted);
  session.UpdatePose(At(0.2), Pose3::Identity(), false);
  ASSERT_TRUE(session.UpdateDepth(At(0.2), test::RenderDepth(k, test::MountPose(), {}), k,
                                  test::MountPose()));
  EXPECT_EQ(session.Cycle(Inputs(0.2, Pose2D{}, {4.0, 0.0})).result, GoalCycleResult::kDriving);
  session.Cancel();
  c = session.Cycle(Inputs(0.3, Pose2D{}, {4.0, 0.0}));
  EXPECT_EQ(c.result, GoalCycleResult::kIdle);
  EXPECT_EQ(c.command.linear_mps, 0.0);
  EXPECT_EQ(c.command.angular_radps, 0.0);
}

}  // namespace
}  // namespace icgm

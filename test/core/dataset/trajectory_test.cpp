#include "core/dataset/trajectory.h"

#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "core/common/status.h"
#include "temp_dir.h"

namespace icgm {
namespace {

using testing::TempDir;

Trajectory RandomTrajectory(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Trajectory traj;
  for (int i = 0; i < n; ++i) {
    StampedPose sp;
    sp.stamp = Time::FromNanoseconds(1305031102175304000LL + i * 33333000LL);
    const Vec3 t(u(*rng), u(*rng), u(*rng));
    const Quat q(u(*rng), u(*rng), u(*rng), u(*rng));
    sp.pose = MakePose(t, q);
    traj.push_back(sp);
  }
  return traj;
}

void ExpectLoadError(const std::string& path, const std::string& reason_part) {
  try {
    ReadTumTrajectory(path);
    ADD_FAILURE() << "expected LoadError for " << path;
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(reason_part), std::string::npos) << e.what();
  }
}

TEST(TrajectoryTest, WriteReadRoundTrip) {
  TempDir dir;
  std::mt19937 rng(1);
  const Trajectory traj = RandomTrajectory(50, &rng);
  const std::string path = dir.File("traj.txt");
  WriteTumTrajectory(path, traj);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const Trajectory back = ReadTumTrajectory(path);
  ASSERT_EQ(back.size(), traj.size());
  for (size_t i = 0; i < traj.size(); ++i) {
    EXPECT_EQ(back[i].stamp, traj[i].stamp);
    EXPECT_LT((back[i].pose.translation() - traj[i].pose.translation()).norm(), 1e-7);
    EXPECT_LT((back[i].pose.linear() - traj[i].pose.linear()).norm(), 1e-7);
  }
}

TEST(TrajectoryTest, KeepsNanosecondStamps) {
  TempDir dir;
  Trajectory traj(1);
  traj[0].stamp = Time::FromNanoseconds(1234567890123LL);
  WriteTumTrajectory(dir.File("t.txt"), traj);
  EXPECT_EQ(ReadTumTrajectory(dir.File("t.txt"))[0].stamp, traj[0].stamp);
}

TEST(TrajectoryTest, WriteReplacesExistingFile) {
  TempDir dir;
  std::mt19937 rng(2);
  const std::string path = dir.Write("t.txt", "garbage that is not a trajectory\n");
  WriteTumTrajectory(path, RandomTrajectory(3, &rng));
  EXPECT_EQ(ReadTumTrajectory(path).size(), 3u);
  WriteTumTrajectory(path, {});
  EXPECT_TRUE(ReadTumTrajectory(path).empty());
}

TEST(TrajectoryTest, WriteToMissingFolderThrows) {
  TempDir dir;
  EXPECT_THROW(WriteTumTrajectory(dir.File("no/such/folder/t.txt"), {}), LoadError);
}

TEST(TrajectoryTest, ReadsCommentsBlankLinesAndUnnormalizedQuaternions) {
  TempDir dir;
  const std::string path = dir.Write("gt.txt",
                                     "# ground truth trajectory\n"
                                     "# timestamp tx ty tz qx qy qz qw\n"
                                     "\n"
                                     "1305031098.6659 1.3563 0.6305 1.6380 0 0 0 2\r\n"
                                     "   \n"
                                     "1305031098.6758 1 2 3 0 0 1 1\n");
  const Trajectory t = ReadTumTrajectory(path);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].stamp, Time::FromNanoseconds(1305031098665900000LL));
  EXPECT_LT((t[0].pose.translation() - Vec3(1.3563, 0.6305, 1.6380)).norm(), 1e-12);
  EXPECT_LT((t[0].pose.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(RotationAngleRad(t[1].pose), M_PI / 2, 1e-12);  // qz = qw: 90 deg about z
  EXPECT_LT((t[1].pose * Vec3(1, 0, 0) - Vec3(1, 3, 3)).norm(), 1e-12);
}

TEST(TrajectoryTest, MalformedFilesThrowWithLine) {
  TempDir dir;
  ExpectLoadError(dir.File("missing.txt"), "cannot open");
  ExpectLoadError(dir.Write("a.txt", "# c\n1.0 1 2 3 0 0 0\n"), "a.txt:2: expected 8 fields");
  ExpectLoadError(dir.Write("b.txt", "1.0 1 2 3 0 0 0 1 9\n"), "b.txt:1: expected 8");
  ExpectLoadError(dir.Write("c.txt", "1.0 1 2 x 0 0 0 1\n"), "bad number 'x'");
  ExpectLoadError(dir.Write("d.txt", "1.0 1 2 nan 0 0 0 1\n"), "bad number 'nan'");
  ExpectLoadError(dir.Write("e.txt", "1.0 1 2 3 0 0 0 0\n"), "zero quaternion");
  ExpectLoadError(dir.Write("f.txt", "1.0.2 1 2 3 0 0 0 1\n"), "bad timestamp");
  ExpectLoadError(dir.Write("g.txt", "1.0 1 2 3e999 0 0 0 1\n"), "bad number");
}

Trajectory TwoPoses(double gap_s) {
  Trajectory t(2);
  t[0].stamp = Time::FromSeconds(10.0);
  t[0].pose = MakePose(Vec3(0, 0, 0), Quat::Identity());
  t[1].stamp = Time::FromSeconds(10.0 + gap_s);
  t[1].pose = MakePose(Vec3(4, -8, 2), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ())));
  return t;
}

TEST(PoseAtTest, InterpolatesBetweenNeighbours) {
  const Trajectory t = TwoPoses(0.08);
  const auto mid = PoseAt(t, Time::FromSeconds(10.02));  // a quarter of the way
  ASSERT_TRUE(mid.has_value());
  EXPECT_LT((mid->translation() - Vec3(1, -2, 0.5)).norm(), 1e-9);
  EXPECT_NEAR(RotationAngleRad(*mid), 0.1, 1e-9);
  const auto end = PoseAt(t, t[1].stamp);
  ASSERT_TRUE(end.has_value());
  EXPECT_TRUE(end->isApprox(t[1].pose, 1e-12));
  const auto start = PoseAt(t, t[0].stamp);
  ASSERT_TRUE(start.has_value());
  EXPECT_TRUE(start->isApprox(t[0].pose, 1e-12));
}

TEST(PoseAtTest, NoExtrapolationNoBridgingOfHoles) {
  const Trajectory t = TwoPoses(0.5);
  EXPECT_FALSE(PoseAt(t, Time::FromSeconds(9.99)).has_value());
  EXPECT_FALSE(PoseAt(t, Time::FromSeconds(10.51)).has_value());
  EXPECT_FALSE(PoseAt(t, Time::FromSeconds(10.25), 0.1).has_value());
  EXPECT_TRUE(PoseAt(t, Time::FromSeconds(10.25), 0.6).has_value());
  EXPECT_TRUE(PoseAt(t, t[0].stamp, 0.1).has_value());  // exact stamps need no gap check
  EXPECT_FALSE(PoseAt(Trajectory{}, Time::FromSeconds(1.0)).has_value());
}

TEST(PoseAtTest, SortedCheck) {
  Trajectory t = TwoPoses(0.1);
  EXPECT_TRUE(IsSortedByStamp(t));
  std::swap(t[0], t[1]);
  EXPECT_FALSE(IsSortedByStamp(t));
  SortByStamp(&t);
  EXPECT_TRUE(IsSortedByStamp(t));
  EXPECT_EQ(Stamps(t), (std::vector<Time>{Time::FromSeconds(10.0), Time::FromSeconds(10.1)}));
}

}  // namespace
}  // namespace icgm

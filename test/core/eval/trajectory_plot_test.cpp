#include "core/eval/trajectory_plot.h"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/eval/plot_axes.h"

namespace icgm {
namespace {

Trajectory Square(double side_m, double z_m) {
  // Walks the square's perimeter in the x-z plane (y constant), 1 m/s, 30 Hz.
  Trajectory t;
  const int per_side = static_cast<int>(30 * side_m);
  const Vec3 corners[4] = {{0, 0, 0}, {side_m, 0, 0}, {side_m, 0, side_m}, {0, 0, side_m}};
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < per_side; ++i) {
      StampedPose sp;
      sp.stamp = Time::FromSeconds(t.size() / 30.0);
      const double s = static_cast<double>(i) / per_side;
      sp.pose = MakePose((1 - s) * corners[c] + s * corners[(c + 1) % 4] + Vec3(0, 0.2, z_m),
                         Quat::Identity());
      t.push_back(sp);
    }
  }
  return t;
}

TEST(PlotAxesTest, NiceTicks) {
  EXPECT_DOUBLE_EQ(NiceTickStep(1.0, 5), 0.2);
  EXPECT_DOUBLE_EQ(NiceTickStep(7.0, 5), 1.0);
  EXPECT_DOUBLE_EQ(NiceTickStep(9.0, 5), 2.0);
  EXPECT_DOUBLE_EQ(NiceTickStep(40.0, 5), 10.0);
  EXPECT_DOUBLE_EQ(NiceTickStep(0.03, 6), 0.005);
  EXPECT_EQ(TickValues(-0.25, 0.5, 0.2), (std::vector<double>{-0.2, 0.0, 0.2, 0.4}));
  EXPECT_EQ(FormatTick(0.4, 0.2), "0.4");
  EXPECT_EQ(FormatTick(-2.0, 1.0), "-2");
  EXPECT_EQ(FormatTick(0.005, 0.005), "0.005");
}

TEST(PlotAxesTest, MapsCornersAndFlipsY) {
  const PlotAxes axes(cv::Rect(100, 50, 400, 200), -1.0, 1.0, 0.0, 2.0);
  EXPECT_NEAR(axes.ToPixel(-1.0, 0.0).x, 100.0, 1e-12);
  EXPECT_NEAR(axes.ToPixel(-1.0, 0.0).y, 250.0, 1e-12);
  EXPECT_NEAR(axes.ToPixel(1.0, 2.0).x, 500.0, 1e-12);
  EXPECT_NEAR(axes.ToPixel(1.0, 2.0).y, 50.0, 1e-12);
}

// Counts pixels close to a BGR colour.
int CountColor(const cv::Mat& img, const cv::Scalar& bgr, int tol = 30) {
  cv::Mat mask;
  cv::inRange(img, bgr - cv::Scalar::all(tol), bgr + cv::Scalar::all(tol), mask);
  return cv::countNonZero(mask);
}

TEST(TrajectoryPlotTest, DrawsBothTrajectoriesInTheWidestPlane) {
  const Trajectory gt = Square(2.0, 0.5);
  Trajectory est = gt;
  for (size_t i = 0; i < est.size(); ++i) est[i].pose.translation().x() += 0.05 * std::sin(0.1 * i);
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, est, {}, &ev).ok());
  TrajectoryPlotOptions opt;
  opt.title = "square";
  const cv::Mat img = RenderTrajectoryPlot(gt, est, ev, opt);
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, opt.width_px);
  EXPECT_GT(CountColor(img, cv::Scalar(180, 119, 31)), 500);    // estimate in blue
  EXPECT_GT(CountColor(img, cv::Scalar(70, 70, 70), 10), 500);  // ground truth in grey
  // The square spans x and z; with equal axis scale it must look square: the ground-truth
  // pixels in the top panel form a bounding box about as wide as high.
  cv::Mat mask;
  const cv::Mat top = img(cv::Rect(95, 78, img.cols - 125, static_cast<int>(0.62 * img.cols)));
  cv::inRange(top, cv::Scalar(60, 60, 60), cv::Scalar(80, 80, 80), mask);
  // Drop the legend (top right) from the mask.
  mask(cv::Rect(mask.cols - 300, 0, 300, 140)).setTo(0);
  const cv::Rect box = cv::boundingRect(mask);
  ASSERT_GT(box.width, 100);
  EXPECT_NEAR(static_cast<double>(box.height) / box.width, 1.0, 0.1);
}

TEST(TrajectoryPlotTest, WritesPngAndReportsBadPath) {
  const Trajectory gt = Square(1.0, 0.0);
  TrajectoryEvaluation ev;
  ASSERT_TRUE(EvaluateTrajectory(gt, gt, {}, &ev).ok());
  const std::string path =
      (std::filesystem::temp_directory_path() / "icgm_trajectory_plot_test.png").string();
  ASSERT_TRUE(WriteTrajectoryPlot(path, gt, gt, ev).ok());
  const cv::Mat back = cv::imread(path);
  EXPECT_FALSE(back.empty());
  std::filesystem::remove(path);
  const Status s = WriteTrajectoryPlot("/no/such/folder/plot.png", gt, gt, ev);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("/no/such/folder/plot.png"), std::string::npos);
}

TEST(TrajectoryPlotTest, EmptyInputGivesMessageNotCrash) {
  const cv::Mat img = RenderTrajectoryPlot({}, {}, TrajectoryEvaluation{});
  EXPECT_FALSE(img.empty());
}

}  // namespace
}  // namespace icgm

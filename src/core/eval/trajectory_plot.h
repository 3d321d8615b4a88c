// A figure of a trajectory evaluation (TrajectoryEvaluation): a top view of ground truth vs.
// the aligned estimate, using the two world axes with the largest extent at equal scale,
// with per-pose error connectors, start/end markers and a legend; below it the ATE of each
// associated pose over time with its RMSE. Drawn with OpenCV, no plotting library.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/dataset/trajectory.h"
#include "core/eval/trajectory_evaluation.h"

namespace icgm {

struct TrajectoryPlotOptions {
  std::string title = "trajectory";  // shown top left
  int width_px = 1100;               // figure width; height follows (about 0.95 x width)
  // Consecutive poses further apart in time than this are not joined (tracking gaps).
  double max_line_gap_s = 0.5;
};

// The figure as a CV_8UC3 image. `groundtruth` and `estimate` are the full trajectories (the
// estimate is drawn through evaluation.alignment); evaluation comes from EvaluateTrajectory.
cv::Mat RenderTrajectoryPlot(const Trajectory& groundtruth, const Trajectory& estimate,
                             const TrajectoryEvaluation& evaluation,
                             const TrajectoryPlotOptions& options = {});

// Renders and writes a PNG; fails with a reason if the file cannot be written.
Status WriteTrajectoryPlot(const std::string& png_path, const Trajectory& groundtruth,
                           const Trajectory& estimate, const TrajectoryEvaluation& evaluation,
                           const TrajectoryPlotOptions& options = {});

}  // namespace icgm

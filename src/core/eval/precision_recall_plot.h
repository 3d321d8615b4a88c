// Figure of a precision-recall curve (SweepPrecisionRecall): precision against recall as the
// loop-acceptance threshold falls, the point of largest recall at 100 % precision marked, the
// counts in the header. Drawn with OpenCV through PlotAxes.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/eval/precision_recall.h"

namespace icgm {

// CV_8UC3 figure, `width_px` wide (at least 400).
cv::Mat RenderPrecisionRecallPlot(const PrecisionRecallCurve& curve, const std::string& title,
                                  int width_px = 800);

// Renders and writes a PNG; fails with a reason if the file cannot be written.
Status WritePrecisionRecallPlot(const std::string& png_path, const PrecisionRecallCurve& curve,
                                const std::string& title, int width_px = 800);

}  // namespace icgm

#include "core/eval/place_truth.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace icgm {

bool PlaceTruth::IsRevisit(int query) const {
  return query >= 0 && query < num_frames() && !same_place[query].empty();
}

bool PlaceTruth::SamePlace(int query, int earlier) const {
  if (query < 0 || query >= num_frames()) return false;
  const std::vector<int>& s = same_place[query];
  return std::binary_search(s.begin(), s.end(), earlier);
}

bool PlaceTruth::Ambiguous(int query, int earlier) const {
  if (query < 0 || query >= static_cast<int>(ambiguous.size())) return false;
  const std::vector<int>& a = ambiguous[query];
  return std::binary_search(a.begin(), a.end(), earlier);
}

bool PlaceTruth::Judged(int query, int earlier) const {
  return Known(query) && Known(earlier) && !Ambiguous(query, earlier);
}

int PlaceTruth::NumAmbiguousPairs() const {
  int n = 0;
  for (const auto& a : ambiguous) n += static_cast<int>(a.size());
  return n;
}

bool PlaceTruth::Known(int frame) const {
  return frame < 0 || frame >= static_cast<int>(unknown.size()) || unknown[frame] == 0;
}

int PlaceTruth::NumUnknown() const {
  return static_cast<int>(std::count(unknown.begin(), unknown.end(), uint8_t{1}));
}

int PlaceTruth::NumRevisits() const {
  int n = 0;
  for (const auto& s : same_place) n += !s.empty();
  return n;
}

PlaceTruth RevisitsFromPoses(const std::vector<std::optional<Pose3>>& poses,
                             const RevisitCriterion& criterion) {
  PlaceTruth truth;
  truth.same_place.resize(poses.size());
  truth.unknown.assign(poses.size(), 0);
  for (size_t i = 0; i < poses.size(); ++i) truth.unknown[i] = poses[i] ? 0 : 1;
  truth.ambiguous.resize(poses.size());
  const double max_angle_rad = criterion.max_angle_deg * M_PI / 180.0;
  const double soft_distance_m = std::max(criterion.max_distance_m, criterion.soft_max_distance_m);
  const double soft_angle_rad =
      std::max(criterion.max_angle_deg, criterion.soft_max_angle_deg) * M_PI / 180.0;
  const int gap = std::max(1, criterion.min_frame_gap);
  for (int i = 0; i < static_cast<int>(poses.size()); ++i) {
    if (!poses[i]) continue;
    for (int j = 0; j <= i - gap; ++j) {
      if (!poses[j]) continue;
      const Pose3 relative = poses[j]->inverse() * *poses[i];
      const double distance_m = relative.translation().norm();
      const double angle_rad = Eigen::AngleAxisd(relative.linear()).angle();
      if (distance_m <= criterion.max_distance_m && angle_rad <= max_angle_rad) {
        truth.same_place[i].push_back(j);
      } else if (distance_m <= soft_distance_m && angle_rad <= soft_angle_rad) {
        truth.ambiguous[i].push_back(j);
      }
    }
  }
  return truth;
}

Status PlaceTruthFromMatrix(const cv::Mat& matrix, int num_frames, int min_frame_gap,
                            PlaceTruth* truth) {
  if (matrix.empty()) return Status::Error("ground-truth matrix is empty");
  if (matrix.rows < num_frames || matrix.cols < num_frames) {
    return Status::Error("ground-truth matrix is " + std::to_string(matrix.cols) + "x" +
                         std::to_string(matrix.rows) + " pixels, fewer than the " +
                         std::to_string(num_frames) + " frames");
  }
  // Any channel > 0, as one 8-bit mask.
  cv::Mat mask = cv::Mat::zeros(matrix.size(), CV_8U);
  std::vector<cv::Mat> channels;
  cv::split(matrix, channels);
  for (const cv::Mat& c : channels) {
    cv::Mat positive;
    cv::compare(c, 0, positive, cv::CMP_GT);
    mask |= positive;
  }
  truth->same_place.assign(num_frames, {});
  const int gap = std::max(1, min_frame_gap);
  for (int i = 0; i < num_frames; ++i) {
    for (int j = 0; j <= i - gap; ++j) {
      if (mask.at<uchar>(i, j) || mask.at<uchar>(j, i)) truth->same_place[i].push_back(j);
    }
  }
  return Status::Ok();
}

}  // namespace icgm

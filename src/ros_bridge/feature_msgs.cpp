#include "ros_bridge/feature_msgs.h"

#include <cstring>

#include "ros_bridge/conversions.h"

namespace icgm::ros_bridge {

icgm_slam::RobustFeatures ToFeaturesMsg(const TrackedFrame& frame, Time reference_stamp,
                                        const std::string& frame_id, double icgm_threshold) {
  icgm_slam::RobustFeatures m;
  m.header.stamp = ToRos(frame.stamp);
  m.header.frame_id = frame_id;
  m.reference_header.stamp = ToRos(reference_stamp);
  m.reference_header.frame_id = frame_id;
  const auto& kps = frame.features.keypoints;
  m.keypoints.resize(kps.size());
  m.robust.resize(kps.size());
  for (size_t i = 0; i < kps.size(); ++i) {
    auto& k = m.keypoints[i];
    k.x = kps[i].pt.x;
    k.y = kps[i].pt.y;
    k.size = kps[i].size;
    k.angle = kps[i].angle;
    k.response = kps[i].response;
    k.octave = kps[i].octave;
    m.robust[i] = i < frame.robust.size() && frame.robust[i];
  }
  const cv::Mat& d = frame.features.descriptors;
  m.descriptor_type = frame.features.binary ? icgm_slam::RobustFeatures::DESCRIPTOR_BINARY
                                            : icgm_slam::RobustFeatures::DESCRIPTOR_FLOAT32;
  m.descriptor_size_bytes = d.empty() ? 0 : static_cast<uint32_t>(d.cols * d.elemSize());
  m.descriptors.resize(static_cast<size_t>(d.rows) * m.descriptor_size_bytes);
  for (int r = 0; r < d.rows; ++r) {
    std::memcpy(&m.descriptors[r * m.descriptor_size_bytes], d.ptr(r), m.descriptor_size_bytes);
  }
  m.matches.resize(frame.matches_to_previous.size());
  for (size_t i = 0; i < frame.matches_to_previous.size(); ++i) {
    m.matches[i].index_current = frame.matches_to_previous[i].queryIdx;
    m.matches[i].index_reference = frame.matches_to_previous[i].trainIdx;
    m.matches[i].kept = i < frame.match_kept.size() && frame.match_kept[i];
  }
  m.icgm_threshold = static_cast<float>(icgm_threshold);
  return m;
}

Status FromFeaturesMsg(const icgm_slam::RobustFeatures& m, TrackedFrame* frame) {
  const size_t n = m.keypoints.size();
  if (m.robust.size() != n) return Status::Error("robust flags do not match keypoint count");
  const bool binary = m.descriptor_type == icgm_slam::RobustFeatures::DESCRIPTOR_BINARY;
  if (!binary && m.descriptor_type != icgm_slam::RobustFeatures::DESCRIPTOR_FLOAT32) {
    return Status::Error("unknown descriptor type " + std::to_string(m.descriptor_type));
  }
  const size_t row_bytes = m.descriptor_size_bytes;
  if (m.descriptors.size() != n * row_bytes || (!binary && row_bytes % 4 != 0)) {
    return Status::Error("descriptor data size " + std::to_string(m.descriptors.size()) +
                         " does not match " + std::to_string(n) + " rows of " +
                         std::to_string(row_bytes) + " bytes");
  }
  TrackedFrame f;
  f.stamp = FromRos(m.header.stamp);
  f.features.binary = binary;
  f.features.keypoints.resize(n);
  f.robust.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& k = m.keypoints[i];
    f.features.keypoints[i] = cv::KeyPoint(k.x, k.y, k.size, k.angle, k.response, k.octave);
    f.robust[i] = m.robust[i] ? 1 : 0;
  }
  if (n > 0 && row_bytes > 0) {
    const int cols = binary ? static_cast<int>(row_bytes) : static_cast<int>(row_bytes / 4);
    f.features.descriptors.create(static_cast<int>(n), cols, binary ? CV_8U : CV_32F);
    std::memcpy(f.features.descriptors.data, m.descriptors.data(), m.descriptors.size());
  }
  f.matches_to_previous.reserve(m.matches.size());
  for (const auto& mm : m.matches) {
    if (mm.index_current < 0 || static_cast<size_t>(mm.index_current) >= n ||
        mm.index_reference < 0) {
      return Status::Error("match index out of range");
    }
    f.matches_to_previous.emplace_back(mm.index_current, mm.index_reference, 0.f);
    f.match_kept.push_back(mm.kept ? 1 : 0);
  }
  *frame = std::move(f);
  return Status::Ok();
}

}  // namespace icgm::ros_bridge

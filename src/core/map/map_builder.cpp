#include "core/map/map_builder.h"

#include <algorithm>
#include <utility>
#include <vector>

namespace icgm {

MapBuilder::MapBuilder(const MapBuilderOptions& options)
    : options_(options), dictionary_(options.dictionary), detector_(options.loop_closure) {}

Status MapBuilder::Reset(HybridMap map) {
  const Status valid = map.Validate();
  if (!valid.ok()) return valid;
  VisualDictionary dictionary(options_.dictionary);
  for (const auto& kf : map.keyframes()) {
    // Replay the recorded words when they fit; otherwise (merged or older maps) search again
    // and record the result, so the next save replays.
    if (!kf.word_ids.empty() && dictionary.AddAssigned(kf.id, kf.descriptors, kf.word_ids).ok()) {
      continue;
    }
    WordAssignment words;
    const Status added = dictionary.Add(kf.id, kf.descriptors, &words);
    if (!added.ok()) {
      return Status::Error("keyframe " + std::to_string(kf.id) + ": " + added.reason());
    }
    map.SetWordIds(kf.id, std::vector<int32_t>(words.begin(), words.end()));
  }
  map.ResumeLast();
  map_ = std::move(map);
  dictionary_ = std::move(dictionary);
  return Status::Ok();
}

namespace {

// Diagonal information of independent translation (sigma_m) and rotation (sigma_rad) noise.
Mat6 IsotropicInformation(double sigma_m, double sigma_rad) {
  Mat6 info = Mat6::Zero();
  info.diagonal() << Vec3::Constant(1 / (sigma_m * sigma_m)),
      Vec3::Constant(1 / (sigma_rad * sigma_rad));
  return info;
}

}  // namespace

Mat6 MapBuilder::DefaultInformation(RelativePoseSource source) const {
  const bool wheel = source == RelativePoseSource::kWheelOdometry;
  return IsotropicInformation(wheel ? options_.map.wheel_sigma_m : options_.map.visual_sigma_m,
                              wheel ? options_.map.wheel_sigma_rad : options_.map.visual_sigma_rad);
}

Mat6 MapBuilder::OdometryInformation(RelativePoseSource source, const Mat6* registration_covariance,
                                     const Pose3* wheel_motion) const {
  // A step the wheels placed is as good as the wheels over its length.
  if (source == RelativePoseSource::kWheelOdometry && wheel_motion && options_.map.wheel_links) {
    return WheelLinkInformation(*wheel_motion);
  }
  if (source != RelativePoseSource::kVisual || !registration_covariance ||
      options_.map.visual_information != VisualInformation::kRegistration ||
      !registration_covariance->allFinite()) {
    return DefaultInformation(source);
  }
  Mat6 covariance = 0.5 * (*registration_covariance + registration_covariance->transpose());
  const double floor_m = options_.map.registration_floor_sigma_m;
  const double floor_rad = options_.map.registration_floor_sigma_rad;
  for (int i = 0; i < 6; ++i) covariance(i, i) += i < 3 ? floor_m * floor_m : floor_rad * floor_rad;
  const Eigen::LDLT<Mat6> ldlt(covariance);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return DefaultInformation(source);
  const Mat6 information = ldlt.solve(Mat6::Identity());
  return information.allFinite() ? information : DefaultInformation(source);
}

Mat6 MapBuilder::WheelLinkInformation(const Pose3& wheel_motion) const {
  const MapOptions& o = options_.map;
  const double d = TranslationNorm(wheel_motion);
  const double sm = o.wheel_link_floor_sigma_m + o.wheel_link_sigma_m_per_m * d;
  const double sr = o.wheel_link_floor_sigma_rad + o.wheel_link_sigma_rad_per_m * d;
  return IsotropicInformation(sm, sr);
}

bool MapBuilder::CorrectWithPoseGraph(int id, KeyframeUpdate* update) {
  std::vector<bool> fixed;
  if (mode_ == MapMode::kLocalization) {
    fixed.assign(static_cast<size_t>(map_.size()), true);
    for (int k : map_.loops()[static_cast<size_t>(map_.current_loop())].keyframe_ids) {
      fixed[static_cast<size_t>(k)] = false;
    }
  }
  std::vector<Pose3> poses;
  const PoseGraphOptimizer optimizer(options_.pose_graph);
  update->pose_graph_status =
      optimizer.Optimize(map_, &poses, &update->pose_graph, fixed.empty() ? nullptr : &fixed);
  if (!update->pose_graph_status.ok()) return false;
  const Status set = map_.SetGlobalPoses(poses);
  if (!set.ok()) {
    update->pose_graph_status = set;
    return false;
  }
  return map_.MarkCorrected(id).ok();
}

LoopClosureResult MapBuilder::Relocalize(const Keyframe& query, const RegisterFn& register_fn,
                                         double path_since_fix_m, int max_id) const {
  LoopClosureResult result;
  WordAssignment words;
  if (const Status q = dictionary_.Quantize(query.descriptors, &words); !q.ok()) {
    result.status = q;
    return result;
  }
  if (static_cast<int>(query.keypoints.size()) < options_.map.min_keyframe_features) {
    result.status = Status::Error("no relocalization: too few features");
    return result;
  }
  std::vector<DictionaryMatch> scores = dictionary_.Score(words);
  scores.erase(std::remove_if(scores.begin(), scores.end(),
                              [&](const DictionaryMatch& m) { return m.keyframe_id >= max_id; }),
               scores.end());
  return detector_.Detect(query, scores, map_, register_fn, path_since_fix_m);
}

Status MapBuilder::AddKeyframe(Keyframe keyframe, const RegisterFn& register_fn,
                               KeyframeUpdate* update, const Mat6* odometry_information,
                               const Pose3* wheel_motion) {
  *update = KeyframeUpdate();
  WordAssignment words;
  const Status quantized = dictionary_.Quantize(keyframe.descriptors, &words);
  if (!quantized.ok()) return quantized;
  if (static_cast<size_t>(keyframe.descriptors.rows) != keyframe.keypoints.size() ||
      keyframe.points_m.size() != keyframe.keypoints.size()) {
    return Status::Error("keyframe rejected: keypoint, descriptor and point counts differ");
  }
  if (map_.current_session() < 0) map_.StartSession("session");
  keyframe.global_pose = map_.PredictGlobalPose(keyframe.relative_pose);
  update->pose_before_correction = keyframe.global_pose;

  const bool enough_features =
      static_cast<int>(keyframe.keypoints.size()) >= options_.map.min_keyframe_features;
  if (enough_features && register_fn) {
    keyframe.session_id = map_.current_session();
    update->loop = detector_.Detect(
        keyframe, dictionary_.Score(words), map_, register_fn,
        map_.PathLengthSinceCorrectionM() + TranslationNorm(keyframe.relative_pose));
  } else {
    update->loop.status = Status::Error(enough_features ? "no loop closure: no registration"
                                                        : "no loop closure: too few features");
  }
  const cv::Mat descriptors = keyframe.descriptors;
  const Mat6 info = odometry_information
                        ? *odometry_information
                        : OdometryInformation(keyframe.relative_source, nullptr, wheel_motion);
  int id = -1;
  const Status added = map_.AddKeyframe(std::move(keyframe), info, &id);
  if (!added.ok()) return added;
  update->keyframe_id = id;
  const Keyframe& added_kf = map_.keyframe(id);
  if (options_.map.wheel_links && wheel_motion && wheel_motion->matrix().allFinite() &&
      added_kf.previous_id >= 0 && added_kf.relative_source == RelativePoseSource::kVisual) {
    Link link;
    link.from_id = added_kf.previous_id;
    link.to_id = id;
    link.type = LinkType::kWheelOdometry;
    link.relative_pose = Orthonormalized(*wheel_motion);
    link.information = WheelLinkInformation(link.relative_pose);
    map_.AddLink(link);
  }
  if (update->loop.status.ok()) {
    for (const auto& e : update->loop.evidence) {
      if (!e.rejected.empty()) continue;
      Link link;
      link.from_id = e.candidate_id;
      link.to_id = id;
      link.type = LinkType::kLoopClosure;
      link.relative_pose = e.registration.relative_pose;
      link.information = e.registration.information;
      link.inliers = e.registration.inliers;
      map_.AddLink(link);
    }
    if (options_.loop_closure.correction == LoopCorrection::kPoseGraph &&
        CorrectWithPoseGraph(id, update)) {
      update->loop_closed = true;
    } else {
      const double alpha = mode_ == MapMode::kMapping ? options_.loop_closure.alpha_mapping
                                                      : options_.loop_closure.alpha_localization;
      const Status corrected = map_.ApplySemiConsensus(id, update->loop.loop_closure_pose, alpha);
      update->loop_closed = corrected.ok();
      if (!corrected.ok()) update->loop.status = corrected;
    }
  }
  update->pose = map_.keyframe(id).global_pose;
  WordAssignment final_words;
  const Status indexed = dictionary_.Add(id, descriptors, &final_words, &words);
  if (indexed.ok()) {
    map_.SetWordIds(id, std::vector<int32_t>(final_words.begin(), final_words.end()));
  }
  return indexed;
}

}  // namespace icgm

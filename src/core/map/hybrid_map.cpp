#include "core/map/hybrid_map.h"

#include <algorithm>
#include <string>

#include "core/map/semi_consensus.h"

namespace icgm {

int HybridMap::StartSession(const std::string& name) {
  SessionRecord session;
  session.id = static_cast<int>(sessions_.size());
  session.name = name;
  sessions_.push_back(session);
  current_session_ = session.id;
  StartLoop();
  return session.id;
}

int HybridMap::StartLoop() {
  if (current_session_ < 0) return StartSession("session");
  // An empty current loop is reused rather than leaving empty loops behind.
  if (current_loop_ >= 0 && loops_[current_loop_].keyframe_ids.empty() &&
      loops_[current_loop_].session_id == current_session_) {
    return current_loop_;
  }
  LoopRecord loop;
  loop.id = static_cast<int>(loops_.size());
  loop.session_id = current_session_;
  loops_.push_back(loop);
  current_loop_ = loop.id;
  return loop.id;
}

int HybridMap::LatestInSession() const {
  for (auto it = keyframes_.rbegin(); it != keyframes_.rend(); ++it) {
    if (it->session_id == current_session_) return it->id;
  }
  return -1;
}

Pose3 HybridMap::PredictGlobalPose(const Pose3& relative_pose) const {
  const int previous = LatestInSession();
  if (previous >= 0) return Compose(keyframes_[previous].global_pose, relative_pose);
  const Pose3 origin =
      current_session_ >= 0 ? sessions_[current_session_].origin : Pose3::Identity();
  return Compose(origin, relative_pose);
}

Status HybridMap::AddKeyframe(Keyframe keyframe, const Mat6& odometry_information, int* id) {
  const size_t n = keyframe.keypoints.size();
  if (static_cast<size_t>(keyframe.descriptors.rows) != n) {
    return Status::Error("keyframe rejected: " + std::to_string(keyframe.descriptors.rows) +
                         " descriptor rows for " + std::to_string(n) + " keypoints");
  }
  if (keyframe.points_m.size() != n) {
    return Status::Error("keyframe rejected: " + std::to_string(keyframe.points_m.size()) +
                         " 3D points for " + std::to_string(n) + " keypoints");
  }
  if (n > 0 && keyframe.descriptors.depth() != CV_8U && keyframe.descriptors.depth() != CV_32F) {
    return Status::Error("keyframe rejected: descriptors must be CV_8U or CV_32F");
  }
  if (current_session_ < 0) StartSession("session");
  keyframe.id = size();
  keyframe.session_id = current_session_;
  keyframe.loop_id = current_loop_;
  keyframe.previous_id = LatestInSession();
  keyframe.global_pose = PredictGlobalPose(keyframe.relative_pose);
  if (keyframe.previous_id < 0) keyframe.relative_source = RelativePoseSource::kSessionStart;
  if (keyframe.previous_id >= 0) {
    Link link;
    link.from_id = keyframe.previous_id;
    link.to_id = keyframe.id;
    link.type = LinkType::kOdometry;
    link.relative_pose = keyframe.relative_pose;
    link.information = odometry_information;
    links_.push_back(link);
  }
  loops_[current_loop_].keyframe_ids.push_back(keyframe.id);
  *id = keyframe.id;
  keyframes_.push_back(std::move(keyframe));
  return Status::Ok();
}

Status HybridMap::AddLink(const Link& link) {
  if (link.from_id < 0 || link.from_id >= size() || link.to_id < 0 || link.to_id >= size()) {
    return Status::Error("link rejected: keyframe ids " + std::to_string(link.from_id) +
                         " -> " + std::to_string(link.to_id) + " not in the map");
  }
  if (link.type == LinkType::kOdometry) {
    return Status::Error("link rejected: odometry links come with their keyframe");
  }
  links_.push_back(link);
  return Status::Ok();
}

void HybridMap::SetWordIds(int id, std::vector<int32_t> word_ids) {
  keyframes_.at(static_cast<size_t>(id)).word_ids = std::move(word_ids);
}

Status HybridMap::ApplySemiConsensus(int id, const Pose3& loop_closure_pose, double alpha) {
  if (!(alpha >= 0.0 && alpha <= 1.0)) {
    return Status::Error("semi-consensus: alpha " + std::to_string(alpha) + " not in [0, 1]");
  }
  if (id < 0 || id >= size() || keyframes_[id].session_id != current_session_ ||
      id != LatestInSession()) {
    return Status::Error("semi-consensus: keyframe " + std::to_string(id) +
                         " is not the latest of the current session");
  }
  SessionRecord& session = sessions_[current_session_];
  const int anchor = CorrectionAnchor();
  std::vector<int> chain;  // b, b-1, ..., a+1
  for (int k = id; k > anchor; k = keyframes_[k].previous_id) chain.push_back(k);
  if (chain.empty())
    return Status::Error("semi-consensus: no relative poses since last correction");
  std::reverse(chain.begin(), chain.end());
  const Pose3 pose_a = anchor >= 0 ? keyframes_[anchor].global_pose : session.origin;
  std::vector<Pose3> relative;
  relative.reserve(chain.size());
  for (int k : chain) relative.push_back(keyframes_[k].relative_pose);
  const std::vector<Pose3> corrected =
      SemiConsensusCorrection(pose_a, relative, loop_closure_pose, alpha);
  Pose3 pose = pose_a;
  for (size_t i = 0; i < chain.size(); ++i) {
    Keyframe& kf = keyframes_[chain[i]];
    kf.relative_pose = corrected[i];
    pose = Compose(pose, corrected[i]);  // eq. 6.1 rebuild
    kf.global_pose = pose;
  }
  session.last_corrected_id = id;
  return Status::Ok();
}

Status HybridMap::SetGlobalPoses(const std::vector<Pose3>& poses) {
  if (poses.size() != keyframes_.size()) {
    return Status::Error("set global poses: " + std::to_string(poses.size()) + " poses for " +
                         std::to_string(keyframes_.size()) + " keyframes");
  }
  for (auto& kf : keyframes_) kf.global_pose = poses[static_cast<size_t>(kf.id)];
  for (auto& kf : keyframes_) {
    const Pose3 parent = kf.previous_id >= 0
                             ? keyframes_[static_cast<size_t>(kf.previous_id)].global_pose
                             : sessions_[static_cast<size_t>(kf.session_id)].origin;
    kf.relative_pose = Between(parent, kf.global_pose);
  }
  return Status::Ok();
}

Status HybridMap::MarkCorrected(int id) {
  if (current_session_ < 0 || id != LatestInSession()) {
    return Status::Error("mark corrected: keyframe " + std::to_string(id) +
                         " is not the latest of the current session");
  }
  sessions_[current_session_].last_corrected_id = id;
  return Status::Ok();
}

int HybridMap::CorrectionAnchor() const {
  int anchor = sessions_[current_session_].last_corrected_id;
  const LoopRecord& loop = loops_[current_loop_];
  if (loop.session_id == current_session_ && !loop.keyframe_ids.empty()) {
    // Earlier learned loops are the reference the current one is corrected against.
    anchor = std::max(anchor, keyframes_[loop.keyframe_ids.front()].previous_id);
  }
  return anchor;
}

double HybridMap::PathLengthSinceCorrectionM() const {
  if (current_session_ < 0) return 0.0;
  const int anchor = CorrectionAnchor();
  double length = 0.0;
  for (int k = LatestInSession(); k > anchor; k = keyframes_[k].previous_id) {
    length += keyframes_[k].relative_pose.translation().norm();
  }
  return length;
}

void HybridMap::Merge(const HybridMap& other, const Pose3& this_from_other) {
  const int kf_offset = size();
  const int session_offset = static_cast<int>(sessions_.size());
  const int loop_offset = static_cast<int>(loops_.size());
  const auto shift = [](int id, int offset) { return id < 0 ? id : id + offset; };
  for (SessionRecord s : other.sessions_) {
    s.id += session_offset;
    s.origin = this_from_other * s.origin;
    s.last_corrected_id = shift(s.last_corrected_id, kf_offset);
    sessions_.push_back(std::move(s));
  }
  for (LoopRecord l : other.loops_) {
    l.id += loop_offset;
    l.session_id += session_offset;
    for (int& k : l.keyframe_ids) k += kf_offset;
    loops_.push_back(std::move(l));
  }
  for (Keyframe kf : other.keyframes_) {
    kf.id += kf_offset;
    kf.session_id += session_offset;
    kf.loop_id += loop_offset;
    kf.previous_id = shift(kf.previous_id, kf_offset);
    kf.global_pose = Orthonormalized(this_from_other * kf.global_pose);
    kf.word_ids.clear();
    keyframes_.push_back(std::move(kf));
  }
  for (Link link : other.links_) {
    link.from_id += kf_offset;
    link.to_id += kf_offset;
    links_.push_back(link);
  }
  if (current_session_ < 0) ResumeLast();
}

Status HybridMap::RestoreSession(const SessionRecord& session) {
  if (session.id != static_cast<int>(sessions_.size())) {
    return Status::Error("session id " + std::to_string(session.id) + " out of order");
  }
  sessions_.push_back(session);
  return Status::Ok();
}

Status HybridMap::RestoreLoop(const LoopRecord& loop) {
  if (loop.id != static_cast<int>(loops_.size())) {
    return Status::Error("loop id " + std::to_string(loop.id) + " out of order");
  }
  loops_.push_back(loop);
  return Status::Ok();
}

Status HybridMap::RestoreKeyframe(Keyframe keyframe) {
  if (keyframe.id != size()) {
    return Status::Error("keyframe id " + std::to_string(keyframe.id) + " out of order");
  }
  keyframes_.push_back(std::move(keyframe));
  return Status::Ok();
}

Status HybridMap::RestoreLink(const Link& link) {
  links_.push_back(link);
  return Status::Ok();
}

Status HybridMap::Validate() const {
  const int n_sessions = static_cast<int>(sessions_.size());
  const int n_loops = static_cast<int>(loops_.size());
  for (const auto& kf : keyframes_) {
    const std::string where = "keyframe " + std::to_string(kf.id) + ": ";
    if (kf.session_id < 0 || kf.session_id >= n_sessions) {
      return Status::Error(where + "unknown session " + std::to_string(kf.session_id));
    }
    if (kf.loop_id < 0 || kf.loop_id >= n_loops) {
      return Status::Error(where + "unknown loop " + std::to_string(kf.loop_id));
    }
    if (kf.previous_id >= kf.id ||
        (kf.previous_id >= 0 && keyframes_[kf.previous_id].session_id != kf.session_id)) {
      return Status::Error(where + "bad previous keyframe " + std::to_string(kf.previous_id));
    }
    const size_t n = kf.keypoints.size();
    if (static_cast<size_t>(kf.descriptors.rows) != n || kf.points_m.size() != n) {
      return Status::Error(where + "feature, descriptor and point counts differ");
    }
  }
  for (const auto& loop : loops_) {
    if (loop.session_id < 0 || loop.session_id >= n_sessions) {
      return Status::Error("loop " + std::to_string(loop.id) + ": unknown session");
    }
    for (int k : loop.keyframe_ids) {
      if (k < 0 || k >= size() || keyframes_[k].loop_id != loop.id) {
        return Status::Error("loop " + std::to_string(loop.id) + ": bad keyframe " +
                             std::to_string(k));
      }
    }
  }
  for (const auto& s : sessions_) {
    if (s.last_corrected_id >= size() ||
        (s.last_corrected_id >= 0 && keyframes_[s.last_corrected_id].session_id != s.id)) {
      return Status::Error("session " + std::to_string(s.id) + ": bad last corrected keyframe");
    }
  }
  for (const auto& link : links_) {
    if (link.from_id < 0 || link.from_id >= size() || link.to_id < 0 || link.to_id >= size()) {
      return Status::Error("link " + std::to_string(link.from_id) + " -> " +
                           std::to_string(link.to_id) + ": keyframe not in the map");
    }
  }
  return Status::Ok();
}

void HybridMap::ResumeLast() {
  current_session_ = sessions_.empty() ? -1 : static_cast<int>(sessions_.size()) - 1;
  current_loop_ = -1;
  for (auto it = loops_.rbegin(); it != loops_.rend(); ++it) {
    if (it->session_id == current_session_) {
      current_loop_ = it->id;
      break;
    }
  }
  if (current_session_ >= 0 && current_loop_ < 0) StartLoop();
}

}  // namespace icgm

// The hybrid map of thesis 6.1.1: metric models (keyframes) with their ICGM features and 3D
// points, chained per session by relative poses (eq. 6.1: L_n = L_(n-1) (+) R_n), odometry links
// between consecutive models and loop-closure links from 6D registration, grouped in learned loops
// (traversals) and sessions (recordings, e.g. under different lighting). Holds the bookkeeping of
// the semi-consensus correction (eq. 6.4): the last corrected keyframe a of each session.
#pragma once

#include <string>
#include <vector>

#include "core/common/pose.h"
#include "core/common/status.h"
#include "core/map/keyframe.h"

namespace icgm {

// kOdometry: R_n between consecutive keyframes of a session (what eq. 6.1 chains), from vision
// or, when registration failed, the wheels. kWheelOdometry: the wheels' own measurement of a
// step whose R_n came from vision, kept beside it so a pose-graph back end can weigh both
// (eq. 6.4 and the chain ignore it). kLoopClosure: 6D registration to an earlier model.
enum class LinkType : int { kOdometry = 0, kLoopClosure = 1, kWheelOdometry = 2 };

// Constraint "to_id expressed in from_id's frame" = relative_pose.
struct Link {
  int from_id = -1;
  int to_id = -1;
  LinkType type = LinkType::kOdometry;
  Pose3 relative_pose = Pose3::Identity();
  Mat6 information = Mat6::Identity();
  int inliers = 0;  // registration inliers (0 for wheel odometry)
};

struct LoopRecord {
  int id = -1;
  int session_id = -1;
  std::vector<int> keyframe_ids;  // in insertion order
};

struct SessionRecord {
  int id = -1;
  std::string name;
  Pose3 origin = Pose3::Identity();  // L_0: world pose the session's chain starts from
  int last_corrected_id = -1;  // keyframe a of eq. 6.4 (-1: none yet, the chain starts at origin)
};

class HybridMap {
 public:
  // Opens a new session (and a new loop in it); later keyframes chain from the session origin.
  int StartSession(const std::string& name);
  // Opens a new learned loop in the current session; the pose chain continues.
  int StartLoop();

  // The pose L_n a keyframe with relative pose R_n would get if added now (eq. 6.1).
  Pose3 PredictGlobalPose(const Pose3& relative_pose) const;
  // Appends to the current loop (a session is started if none): assigns id/session/loop/
  // previous_id and global pose by eq. 6.1 and adds the odometry link from the previous keyframe.
  // Fails when descriptors, keypoints and points disagree in count.
  Status AddKeyframe(Keyframe keyframe, const Mat6& odometry_information, int* id);
  // A loop-closure or wheel-odometry link between existing keyframes (odometry links are added
  // by AddKeyframe).
  Status AddLink(const Link& link);
  // Records the dictionary words of keyframe `id` (see Keyframe::word_ids).
  void SetWordIds(int id, std::vector<int32_t> word_ids);

  // Eq. 6.4 on the current session: spreads alpha of the difference between the current pose of
  // keyframe `id` (must be the session's latest) and `loop_closure_pose` over the relative poses
  // after the anchor a, rebuilds the global poses, and makes `id` the new anchor. The anchor is
  // the session's last corrected keyframe, but never before the current loop: earlier learned
  // loops are the reference and are not moved by the current traversal's corrections.
  Status ApplySemiConsensus(int id, const Pose3& loop_closure_pose, double alpha);
  // Replaces the global poses L_n of all keyframes (`poses` indexed by id, size() entries) and
  // keeps the chain consistent: R_n = L_(n-1)^-1 L_n, or origin^-1 L_n for a session's first
  // keyframe. Odometry links keep their measurements. Used by a full pose-graph back end.
  Status SetGlobalPoses(const std::vector<Pose3>& poses);
  // Makes keyframe `id` (the latest of the current session) the anchor a of eq. 6.4 and of
  // PathLengthSinceCorrectionM, as after a correction by another back end.
  Status MarkCorrected(int id);
  // Path length (sum of |t(R_k)|) of the current session after the eq. 6.4 anchor.
  double PathLengthSinceCorrectionM() const;

  // Appends all of `other` (sessions, loops, keyframes, links), re-numbering its ids after ours.
  // `this_from_other` maps other's world frame into ours (identity: shared start point).
  // The merged keyframes' word ids belong to another dictionary and are cleared.
  void Merge(const HybridMap& other, const Pose3& this_from_other = Pose3::Identity());

  // Loading: appends records verbatim (ids must be dense and in order); used by MapStore.
  Status RestoreSession(const SessionRecord& session);
  Status RestoreLoop(const LoopRecord& loop);
  Status RestoreKeyframe(Keyframe keyframe);
  Status RestoreLink(const Link& link);
  // Consistency after a restore: keyframes reference existing sessions/loops/previous ids.
  Status Validate() const;
  // Makes the last session/loop current (after loading, new keyframes extend the last session).
  void ResumeLast();

  int size() const { return static_cast<int>(keyframes_.size()); }
  bool empty() const { return keyframes_.empty(); }
  const Keyframe& keyframe(int id) const { return keyframes_.at(static_cast<size_t>(id)); }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<LoopRecord>& loops() const { return loops_; }
  const std::vector<SessionRecord>& sessions() const { return sessions_; }
  int current_session() const { return current_session_; }
  int current_loop() const { return current_loop_; }
  // Latest keyframe of the current session (-1: none).
  int LatestInSession() const;

 private:
  // Keyframe a of eq. 6.4 for the current session (-1: the session origin).
  int CorrectionAnchor() const;

  std::vector<Keyframe> keyframes_;
  std::vector<Link> links_;
  std::vector<LoopRecord> loops_;
  std::vector<SessionRecord> sessions_;
  int current_session_ = -1;
  int current_loop_ = -1;
};

}  // namespace icgm

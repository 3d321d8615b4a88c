// icgm_rgbd_scene_stats: measures what a crowd sequence offers an RGB-D front end, the same way
// for a real TUM-layout folder and a rendered scenario, so the two can be compared side by side:
// keypoints per frame (and those with depth, near and far), depth coverage and range, how much
// of the image lies near the camera (people stand 0.5-2.5 m away, the room's walls further),
// image sharpness (blur), the depth step between neighbouring pixels on far surfaces (sensor
// noise and quantization), and the camera's motion per frame from the ground truth. A rendered
// scenario also reports the walkers' true share of the image and of the keypoints (its masks).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/common/pose.h"
#include "core/common/progress_bar.h"
#include "core/common/status.h"
#include "core/dataset/camera_options.h"
#include "core/dataset/trajectory.h"
#include "core/dataset/tum_dataset.h"
#include "core/eval/background_depth.h"
#include "core/eval/keypoint_repeatability.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/features/lens_undistortion.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_rgbd_scene_stats (--tum DIR [--camera camera.yaml] | --sim SCENARIO.yaml\n"
    "                              [--sim-seed N]) [--near-m 2.5] [--max-frames N] [--csv OUT]\n"
    "                             [--max-features 1000] [--gap 1] [--room-min-depth-m M]\n"
    "                             [--images-out DIR [--image-every 50]] [--foreground-every N]\n"
    "  Per sequence (mean and 10/50/90th percentiles over frames): ORB keypoints (1000 at\n"
    "  most, as the front end extracts them), those with depth, with depth < near-m and\n"
    "  beyond; valid depth share and the depth's 10/50/90th percentiles; the image share nearer\n"
    "  than near-m; sharpness (mean Sobel gradient magnitude of the grey image, overall and on\n"
    "  far pixels); on surfaces 2.5-4.5 m away, the median non-zero depth step between\n"
    "  horizontal neighbours and the share of equal neighbours (noise, quantization); camera\n"
    "  motion per frame (ground truth); missing depth (image shares) in runs along rows between\n"
    "  valid pixels of depths more than 10% apart (edges, near side < near-m or both far), alike\n"
    "  (holes in near / far surfaces) or reaching the border, and the keypoints without depth.\n"
    "  --sim adds the\n"
    "  walkers' image share and keypoints on walkers (simulator's masks). --csv writes the\n"
    "  per-frame values.\n"
    "  Room keypoints under the true motion (frame pairs i - gap, i, with ground truth): the\n"
    "  keypoints with depth of at least --room-min-depth-m (default: --near-m; people stand\n"
    "  nearer) and, rendered, outside the walkers' masks, back-projected and moved by the true\n"
    "  motion into the later frame where it sees them: the share with a keypoint detected\n"
    "  within 1 / 2 px (repeatability), the share matched by descriptor (ratio 0.8, against all\n"
    "  of the later frame's keypoints), the matches' share within 3 px and their error (median,\n"
    "  90th percentile, share above 1 / 2 px, pooled over pairs), each after removing the pair's\n"
    "  common image shift (the ground truth's own error; its size is printed too).\n"
    "  A camera with lens distortion: these use keypoints and depth moved to the pinhole image,\n"
    "  as the front end does. --max-features sets the ORB budget (1000 as the front end).\n"
    "  --foreground-every N (with ground truth): every N-th frame, the share of the image in\n"
    "  front of the room's depth (the median depth the other sampled frames saw along each\n"
    "  ray, core/eval/background_depth.h) by more than 0.3 m and 10%: how much of the view\n"
    "  walkers cover, measured alike with and without masks (--sim also prints the masks'\n"
    "  share and the estimate's agreement with them).\n"
    "  --images-out writes every image-every'th colour image as DIR/NNNN.png (to look at the\n"
    "  real and the rendered images side by side).\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_rgbd_scene_stats", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

struct FrameStats {
  double keypoints = 0, keypoints_depth = 0, keypoints_near = 0, keypoints_far = 0;
  double valid_share = 0, depth_p10 = 0, depth_p50 = 0, depth_p90 = 0, near_share = 0;
  double gradient = 0, gradient_far = 0, far_step_mm = 0, far_flat_share = 0;
  double motion_mm = NAN, motion_deg = NAN;
  // Missing depth by where it lies (image shares): runs of invalid pixels along a row, between
  // valid neighbours whose depths differ by more than 10% (an object's edge; "near" when the
  // nearer side is nearer than near_m) or alike (a hole in a surface, by its depth), or
  // reaching the image's border; and the share of keypoints without depth.
  double missing_edge_near = 0, missing_edge_far = 0, missing_surface_near = 0;
  double missing_surface_far = 0, missing_border = 0, keypoints_no_depth = 0;
  double walker_share = NAN, keypoints_walker = NAN, keypoints_static_depth = NAN;
  // Room keypoints of the frame `gap` before, under the true motion (NaN without a pair).
  double room_keypoints = NAN, room_repeated_1px = NAN, room_repeated_2px = NAN;
  double room_matched = NAN, room_matched_correct = NAN, room_shift_px = NAN;
};

// One frame as the room-keypoint pairs need it: pinhole keypoints, depth, mask, true pose.
struct PairFrame {
  icgm::FeatureSet features;
  cv::Mat depth_m, mask;
  std::optional<icgm::Pose3> T_world_camera;
};

// Pools the correct matches' errors over all pairs.
struct RoomErrors {
  std::vector<double> corrected_px, raw_px;
};

double Quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return NAN;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

FrameStats Measure(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& mask, double near_m,
                   const icgm::FeatureSet& features) {
  FrameStats s;
  s.keypoints = features.size();
  if (!mask.empty()) s.keypoints_walker = s.keypoints_static_depth = 0;
  for (const cv::KeyPoint& k : features.keypoints) {
    const int u = std::clamp(static_cast<int>(std::lround(k.pt.x)), 0, depth_m.cols - 1);
    const int v = std::clamp(static_cast<int>(std::lround(k.pt.y)), 0, depth_m.rows - 1);
    const float z = depth_m.at<float>(v, u);
    const bool walker = !mask.empty() && mask.at<uint8_t>(v, u) != 0;
    if (!mask.empty()) s.keypoints_walker += walker;
    if (!std::isfinite(z) || z <= 0.f) continue;
    ++s.keypoints_depth;
    (z < near_m ? s.keypoints_near : s.keypoints_far) += 1;
    if (!mask.empty() && !walker) ++s.keypoints_static_depth;
  }
  cv::Mat grey, gx, gy, magnitude;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3);
  cv::magnitude(gx, gy, magnitude);
  s.gradient = cv::mean(magnitude)[0];
  std::vector<double> depths, steps;
  depths.reserve(depth_m.total());
  double far_gradient = 0, far_count = 0, near_count = 0, walker_count = 0;
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_m.ptr<float>(v);
    const float* m = magnitude.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!mask.empty()) walker_count += mask.at<uint8_t>(v, u) != 0;
      if (!std::isfinite(z[u]) || z[u] <= 0.f) continue;
      depths.push_back(z[u]);
      if (z[u] < near_m) {
        ++near_count;
        continue;
      }
      far_gradient += m[u];
      ++far_count;
      if (u + 1 < depth_m.cols && z[u] >= 2.5f && z[u] <= 4.5f && std::isfinite(z[u + 1])) {
        const double d = std::abs(z[u + 1] - z[u]);
        if (d < 0.1) steps.push_back(d * 1000.0);
      }
    }
  }
  const double pixels = static_cast<double>(depth_m.total());
  s.valid_share = depths.size() / pixels;
  s.near_share = near_count / pixels;
  s.gradient_far = far_count > 0 ? far_gradient / far_count : NAN;
  s.depth_p10 = Quantile(depths, 0.1);
  s.depth_p50 = Quantile(depths, 0.5);
  s.depth_p90 = Quantile(depths, 0.9);
  // Quantized depth (structured light) repeats the same value between neighbours; white noise
  // never does. Steps: the median of the non-zero ones.
  const size_t all_steps = steps.size();
  steps.erase(std::remove(steps.begin(), steps.end(), 0.0), steps.end());
  s.far_flat_share = all_steps ? 1.0 - static_cast<double>(steps.size()) / all_steps : NAN;
  s.far_step_mm = Quantile(steps, 0.5);
  if (!mask.empty()) s.walker_share = walker_count / pixels;
  s.keypoints_no_depth = s.keypoints > 0 ? 1.0 - s.keypoints_depth / s.keypoints : NAN;
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_m.ptr<float>(v);
    const auto valid = [&](int u) { return std::isfinite(z[u]) && z[u] > 0.f; };
    for (int u = 0; u < depth_m.cols;) {
      if (valid(u)) {
        ++u;
        continue;
      }
      const int start = u;
      while (u < depth_m.cols && !valid(u)) ++u;
      const double run = (u - start) / pixels;
      if (start == 0 || u == depth_m.cols) {
        s.missing_border += run;
        continue;
      }
      const float nearer = std::min(z[start - 1], z[u]), further = std::max(z[start - 1], z[u]);
      const bool edge = further - nearer > 0.1f * nearer;
      const bool near = nearer < near_m;
      (edge ? (near ? s.missing_edge_near : s.missing_edge_far)
            : (near ? s.missing_surface_near : s.missing_surface_far)) += run;
    }
  }
  return s;
}

// Room keypoints of `a` in `b` under the true motion; fills s's room fields and pools errors.
void MeasurePair(const PairFrame& a, const PairFrame& b, const icgm::CameraIntrinsics& K,
                 const icgm::DescriptorMatcher& matcher,
                 const icgm::KeypointRepeatabilityOptions& options, FrameStats* s,
                 RoomErrors* errors) {
  if (!a.T_world_camera || !b.T_world_camera) return;
  const icgm::Pose3 b_from_a = b.T_world_camera->inverse() * *a.T_world_camera;
  const std::vector<cv::DMatch> matches = matcher.Match(a.features, b.features);
  const icgm::KeypointRepeatabilityStats r = icgm::MeasureKeypointRepeatability(
      a.features.keypoints, a.depth_m, a.mask, b.features.keypoints, b.depth_m, b.mask, matches, K,
      b_from_a, options);
  s->room_keypoints = r.room_keypoints;
  if (r.room_keypoints == 0) return;
  const double n = r.room_keypoints;
  s->room_repeated_1px = r.repeated_1px / n;
  s->room_repeated_2px = r.repeated_2px / n;
  s->room_matched = r.matched / n;
  s->room_matched_correct =
      r.matched > 0 ? static_cast<double>(r.matched_correct) / r.matched : NAN;
  s->room_shift_px = r.shift_support > 0 ? r.common_shift_px.norm() : NAN;
  errors->corrected_px.insert(errors->corrected_px.end(), r.correct_errors_px.begin(),
                              r.correct_errors_px.end());
  errors->raw_px.insert(errors->raw_px.end(), r.raw_errors_px.begin(), r.raw_errors_px.end());
}

void PrintErrors(const char* name, const std::vector<double>& e) {
  if (e.empty()) return;
  const double above1 = std::count_if(e.begin(), e.end(), [](double x) { return x > 1.0; });
  const double above2 = std::count_if(e.begin(), e.end(), [](double x) { return x > 2.0; });
  std::printf("%-34s p50 %6.3f   p90 %6.3f   > 1 px %5.1f%%   > 2 px %5.1f%%   (n %zu)\n", name,
              Quantile(e, 0.5), Quantile(e, 0.9), 100.0 * above1 / e.size(),
              100.0 * above2 / e.size(), e.size());
}

void SetMotion(const icgm::Pose3& a, const icgm::Pose3& b, FrameStats* s) {
  const icgm::Pose3 d = icgm::Between(a, b);
  s->motion_mm = 1000.0 * icgm::TranslationNorm(d);
  s->motion_deg = icgm::RotationAngleRad(d) * 180.0 / M_PI;
}

void Print(const char* name, const std::vector<FrameStats>& frames, double FrameStats::*field) {
  std::vector<double> v;
  for (const FrameStats& f : frames) v.push_back(f.*field);
  double sum = 0;
  size_t n = 0;
  for (double x : v) {
    if (std::isfinite(x)) sum += x, ++n;
  }
  if (n == 0) return;
  std::printf("%-34s mean %9.3f   p10 %9.3f   p50 %9.3f   p90 %9.3f\n", name, sum / n,
              Quantile(v, 0.1), Quantile(v, 0.5), Quantile(v, 0.9));
}

}  // namespace

int main(int argc, char** argv) {
  std::string tum_dir, sim_path, camera_path, csv_path, images_dir;
  int image_every = 50, foreground_every = 0;
  double near_m = 2.5;
  int max_frames = -1, max_features = 1000, gap = 1;
  std::optional<double> room_min_depth_m;
  std::optional<int> sim_seed;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"tum", "camera", "sim", "sim-seed", "near-m", "max-frames", "csv", "max-features", "gap",
         "room-min-depth-m", "images-out", "image-every", "foreground-every"},
        {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      return UsageError("unexpected argument '" + args.positional().front() + "'");
    }
    tum_dir = args.Get("tum");
    sim_path = args.Get("sim");
    if (tum_dir.empty() == sim_path.empty()) return UsageError("give exactly one of --tum, --sim");
    camera_path = args.Get("camera");
    csv_path = args.Get("csv");
    near_m = args.GetDouble("near-m", near_m);
    max_frames = args.GetInt("max-frames", max_frames);
    if (args.Has("sim-seed")) sim_seed = args.GetInt("sim-seed", 0);
    max_features = args.GetInt("max-features", max_features);
    images_dir = args.Get("images-out");
    image_every = args.GetInt("image-every", image_every);
    if (image_every < 1) return UsageError("--image-every must be >= 1");
    foreground_every = args.GetInt("foreground-every", foreground_every);
    if (foreground_every < 0) return UsageError("--foreground-every must be >= 0");
    gap = args.GetInt("gap", gap);
    if (args.Has("room-min-depth-m")) room_min_depth_m = args.GetDouble("room-min-depth-m", 0.0);
    if (!(near_m > 0.0)) return UsageError("--near-m must be > 0");
    if (max_features < 1) return UsageError("--max-features must be >= 1");
    if (gap < 1) return UsageError("--gap must be >= 1");
    if (room_min_depth_m && !(*room_min_depth_m >= 0.0)) {
      return UsageError("--room-min-depth-m must be >= 0");
    }
  } catch (const std::exception& e) {
    return UsageError(e.what());
  }

  try {
    icgm::FeatureOptions feature_options;
    feature_options.max_features = max_features;
    auto extractor = icgm::FeatureExtractor::Create(feature_options);
    const icgm::DescriptorMatcher matcher{icgm::MatcherOptions()};
    icgm::KeypointRepeatabilityOptions room_options;
    room_options.min_depth_m = room_min_depth_m.value_or(near_m);
    std::vector<FrameStats> frames;
    const auto save = [&](size_t i, const cv::Mat& bgr) {
      if (images_dir.empty() || i % image_every != 0) return;
      char name[32];
      std::snprintf(name, sizeof(name), "/%04zu.png", i);
      if (!cv::imwrite(images_dir + name, bgr)) {
        throw std::runtime_error("cannot write " + images_dir + name);
      }
    };
    std::vector<cv::Mat> sampled_depths, sampled_masks;
    std::vector<icgm::Pose3> sampled_poses;
    const auto sample = [&](size_t i, const PairFrame& f) {
      if (foreground_every == 0 || i % foreground_every != 0 || !f.T_world_camera) return;
      sampled_depths.push_back(f.depth_m);
      sampled_masks.push_back(f.mask);
      sampled_poses.push_back(*f.T_world_camera);
    };
    std::deque<PairFrame> window;  // the last gap + 1 frames
    RoomErrors room_errors;
    icgm::CameraIntrinsics camera;
    // Adds frame `f` to the window and measures it against the frame `gap` before.
    const auto pair = [&](PairFrame f, const icgm::CameraIntrinsics& K, FrameStats* s) {
      window.push_back(std::move(f));
      if (window.size() > static_cast<size_t>(gap) + 1) window.pop_front();
      if (window.size() == static_cast<size_t>(gap) + 1) {
        MeasurePair(window.front(), window.back(), K, matcher, room_options, s, &room_errors);
      }
    };
    if (!tum_dir.empty()) {
      const icgm::CameraIntrinsics K = camera_path.empty()
                                           ? icgm::CameraIntrinsics()
                                           : icgm::LoadCameraIntrinsics(camera_path);
      const icgm::TumDataset data = icgm::TumDataset::Open(tum_dir, K);
      size_t n = data.size();
      if (max_frames > 0) n = std::min(n, static_cast<size_t>(max_frames));
      icgm::ProgressBar bar(n, "scene stats");
      std::optional<icgm::Pose3> previous;
      const icgm::LensUndistortion undistortion(K);
      camera = K;
      for (size_t i = 0; i < n; ++i) {
        const cv::Mat bgr = data.LoadBgr(i), depth_m = data.LoadDepthM(i);
        save(i, bgr);
        PairFrame f;
        f.features = extractor->Extract(bgr);
        FrameStats s = Measure(bgr, depth_m, cv::Mat(), near_m, f.features);
        if (data.has_groundtruth()) {
          const auto pose = icgm::PoseAt(data.groundtruth(), data.frame(i).stamp);
          if (pose && previous) SetMotion(*previous, *pose, &s);
          previous = pose;
          f.T_world_camera = pose;
        }
        undistortion.MoveKeypoints(&f.features.keypoints);
        f.depth_m = undistortion.Depth(depth_m);
        sample(i, f);
        pair(std::move(f), K, &s);
        frames.push_back(s);
        bar.Update(i + 1);
      }
      bar.Finish();
    } else {
      icgm::sim::SimOptions options = icgm::sim::LoadSimOptions(sim_path);
      if (sim_seed) options.seed = *sim_seed;
      const icgm::sim::Simulator sim(options);
      camera = sim.intrinsics();
      size_t n = sim.size();
      if (max_frames > 0) n = std::min(n, static_cast<size_t>(max_frames));
      icgm::ProgressBar bar(n, "scene stats");
      for (size_t i = 0; i < n; ++i) {
        const icgm::sim::SimFrame f = sim.Render(i);
        save(i, f.bgr);
        PairFrame p;
        p.features = extractor->Extract(f.bgr);
        FrameStats s = Measure(f.bgr, f.depth_m, f.dynamic_mask, near_m, p.features);
        if (i > 0) SetMotion(sim.T_world_camera(i - 1), sim.T_world_camera(i), &s);
        p.depth_m = f.depth_m;
        p.mask = f.dynamic_mask;
        p.T_world_camera = sim.T_world_camera(i);
        sample(i, p);
        pair(std::move(p), sim.intrinsics(), &s);
        frames.push_back(s);
        bar.Update(i + 1);
      }
      bar.Finish();
    }
    std::printf("frames: %zu (near: depth < %.2f m)\n", frames.size(), near_m);
    Print("keypoints", frames, &FrameStats::keypoints);
    Print("keypoints with depth", frames, &FrameStats::keypoints_depth);
    Print("keypoints near", frames, &FrameStats::keypoints_near);
    Print("keypoints far", frames, &FrameStats::keypoints_far);
    Print("keypoints on walkers (mask)", frames, &FrameStats::keypoints_walker);
    Print("static keypoints with depth (mask)", frames, &FrameStats::keypoints_static_depth);
    Print("valid depth share", frames, &FrameStats::valid_share);
    Print("missing depth at edges, near side", frames, &FrameStats::missing_edge_near);
    Print("missing depth at edges, both far", frames, &FrameStats::missing_edge_far);
    Print("missing depth in near surfaces", frames, &FrameStats::missing_surface_near);
    Print("missing depth in far surfaces", frames, &FrameStats::missing_surface_far);
    Print("missing depth reaching the border", frames, &FrameStats::missing_border);
    Print("keypoints without depth (share)", frames, &FrameStats::keypoints_no_depth);
    Print("depth p10 [m]", frames, &FrameStats::depth_p10);
    Print("depth p50 [m]", frames, &FrameStats::depth_p50);
    Print("depth p90 [m]", frames, &FrameStats::depth_p90);
    Print("image share near", frames, &FrameStats::near_share);
    Print("image share on walkers (mask)", frames, &FrameStats::walker_share);
    Print("gradient [grey/px]", frames, &FrameStats::gradient);
    Print("gradient on far pixels", frames, &FrameStats::gradient_far);
    Print("far depth step, non-zero [mm]", frames, &FrameStats::far_step_mm);
  Print("far neighbours of equal depth", frames, &FrameStats::far_flat_share);
    Print("motion per frame [mm]", frames, &FrameStats::motion_mm);
    Print("motion per frame [deg]", frames, &FrameStats::motion_deg);
    std::printf("room keypoints (depth >= %.2f m%s) under the true motion, gap %d:\n",
                room_options.min_depth_m, sim_path.empty() ? "" : ", outside the masks", gap);
    Print("  visible in the later frame", frames, &FrameStats::room_keypoints);
    Print("  repeated within 1 px", frames, &FrameStats::room_repeated_1px);
    Print("  repeated within 2 px", frames, &FrameStats::room_repeated_2px);
    Print("  matched by descriptor", frames, &FrameStats::room_matched);
    Print("  matches within 3 px", frames, &FrameStats::room_matched_correct);
    Print("  common shift [px]", frames, &FrameStats::room_shift_px);
    PrintErrors("  error within 3 px, shift removed", room_errors.corrected_px);
    PrintErrors("  the same, shift kept", room_errors.raw_px);
    if (sampled_depths.size() >= 4) {
      std::vector<double> share, mask_share, agree;
      for (size_t t = 0; t < sampled_depths.size(); ++t) {
        std::vector<cv::Mat> depths;
        std::vector<icgm::Pose3> poses;
        for (size_t k = 0; k < sampled_depths.size(); ++k) {
          if (k == t) continue;
          depths.push_back(sampled_depths[k]);
          poses.push_back(sampled_poses[k]);
        }
        const cv::Mat background = icgm::BackgroundDepth(depths, poses, sampled_poses[t], camera);
        const cv::Mat fg = icgm::ForegroundMask(sampled_depths[t], background);
        const double pixels = static_cast<double>(fg.total());
        share.push_back(cv::countNonZero(fg) / pixels);
        const cv::Mat& truth = sampled_masks[t];
        if (truth.empty()) continue;
        mask_share.push_back(cv::countNonZero(truth) / pixels);
        cv::Mat both, either;
        cv::bitwise_and(fg, truth, both);
        cv::bitwise_or(fg, truth, either);
        const int union_px = cv::countNonZero(either);
        agree.push_back(union_px > 0 ? cv::countNonZero(both) / static_cast<double>(union_px)
                                     : 1.0);
      }
      std::printf("in front of the room's depth, every %d frames (%zu frames):\n", foreground_every,
                  sampled_depths.size());
      const auto print = [](const char* name, const std::vector<double>& v) {
        if (v.empty()) return;
        double sum = 0;
        for (double x : v) sum += x;
        std::printf("%-34s mean %9.3f   p10 %9.3f   p50 %9.3f   p90 %9.3f\n", name, sum / v.size(),
                    Quantile(v, 0.1), Quantile(v, 0.5), Quantile(v, 0.9));
      };
      print("  image share", share);
      print("  walkers' share (mask)", mask_share);
      print("  overlap with the mask (IoU)", agree);
    }
    if (!csv_path.empty()) {
      std::ofstream csv(csv_path);
      csv << "frame,keypoints,keypoints_depth,keypoints_near,keypoints_far,keypoints_walker,"
             "static_keypoints_depth,valid_share,depth_p10,depth_p50,depth_p90,near_share,"
             "walker_share,gradient,gradient_far,far_step_mm,far_flat_share,motion_mm,motion_deg,"
             "room_keypoints,room_repeated_1px,room_repeated_2px,room_matched,"
             "room_matched_correct,room_shift_px\n";
      for (size_t i = 0; i < frames.size(); ++i) {
        const FrameStats& s = frames[i];
        csv << i << ',' << s.keypoints << ',' << s.keypoints_depth << ',' << s.keypoints_near << ','
            << s.keypoints_far << ',' << s.keypoints_walker << ',' << s.keypoints_static_depth
            << ',' << s.valid_share << ',' << s.depth_p10 << ',' << s.depth_p50 << ','
            << s.depth_p90 << ',' << s.near_share << ',' << s.walker_share << ',' << s.gradient
            << ',' << s.gradient_far << ',' << s.far_step_mm << ',' << s.far_flat_share << ','
            << s.motion_mm << ',' << s.motion_deg << ',' << s.room_keypoints << ','
            << s.room_repeated_1px << ',' << s.room_repeated_2px << ',' << s.room_matched << ','
            << s.room_matched_correct << ',' << s.room_shift_px << '\n';
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_rgbd_scene_stats: %s\n", e.what());
    return 1;
  }
  return 0;
}

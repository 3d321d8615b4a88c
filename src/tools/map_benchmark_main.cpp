// icgm_map_benchmark: speed and memory of the incremental dictionary and loop-closure query on a
// synthetic map. Keyframes view places of a route driven `--laps` times; each place owns
// `--features` ORB-like 256-bit descriptors with per-bit biases (as real ORB bits are not
// uniform), and a view keeps 85 % of them with a few bits flipped. Prints per-keyframe query and
// insert times (whole run and the last 10 %), memory per keyframe and revisit recall.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/common/thread_cpu_time.h"
#include "core/map/map_builder.h"
#include "core/map/map_options.h"
#include "core/map/map_store.h"
#include "tools/cli_args.h"
#include "tools/timing_series.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_map_benchmark [--keyframes N=5000] [--features N=300] [--laps N=2]\n"
    "                          [--config config/map.yaml] [--seed N=1] [--save MAP.db]\n"
    "  --save also times SaveMap, LoadMap and the dictionary rebuild of MapBuilder::Reset.";
constexpr icgm::tools::ToolInfo kTool{"icgm_map_benchmark", kUsage};

using icgm::tools::TimingSeries;

using icgm::ThreadCpuMs;

double Ms(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

int main(int argc, char** argv) {
  int keyframes = 0;
  int features = 0;
  int laps = 0;
  unsigned seed = 1;
  std::string save_path;
  icgm::MapBuilderOptions options;
  try {
    const icgm::tools::CliArgs args(
        argc, argv, {"keyframes", "features", "laps", "config", "seed", "save"}, {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      throw std::invalid_argument("unexpected argument '" + args.positional().front() + "'");
    }
    keyframes = args.GetInt("keyframes", 5000);
    features = args.GetInt("features", 300);
    laps = args.GetInt("laps", 2);
    seed = static_cast<unsigned>(args.GetInt("seed", 1));
    save_path = args.Get("save");
    if (keyframes < 1 || features < 1 || laps < 1) {
      throw std::invalid_argument("--keyframes, --features and --laps must be >= 1");
    }
    if (args.Has("config")) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(args.Get("config")), &options);
    }
  } catch (const icgm::LoadError& e) {
    return icgm::tools::Failure(kTool, e.what());
  } catch (const std::invalid_argument& e) {
    return icgm::tools::UsageError(kTool, e.what());
  }
  options.dictionary.descriptor_type = icgm::DescriptorType::kBinary;

  // Places with biased bits: P(bit = 1) drawn in [0.25, 0.75] once per bit position.
  const int places = std::max(1, keyframes / laps);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> bias_dist(0.25, 0.75);
  std::vector<double> bias(256);
  for (double& b : bias) b = bias_dist(rng);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto random_descriptor = [&](uint8_t* d) {
    for (int bit = 0; bit < 256; ++bit) {
      if (u(rng) < bias[bit]) d[bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
    }
  };
  std::vector<cv::Mat> place_descriptors(static_cast<size_t>(places));
  for (auto& m : place_descriptors) {
    m = cv::Mat::zeros(features, 32, CV_8U);
    for (int r = 0; r < features; ++r) random_descriptor(m.ptr<uint8_t>(r));
  }
  std::uniform_int_distribution<int> bit_dist(0, 255);

  icgm::MapBuilder builder(options);
  // Registration is not what is measured: reject quickly, so every query runs the full
  // candidate selection without a correction.
  const icgm::RegisterFn no_registration = [](const icgm::Keyframe&, const icgm::Keyframe&) {
    icgm::RegistrationOutcome out;
    out.status = icgm::Status::Error("registration skipped in benchmark");
    return out;
  };
  TimingSeries query;
  TimingSeries query_cpu;
  TimingSeries insert;
  TimingSeries total;
  TimingSeries total_cpu;
  int revisits = 0;
  int recalled = 0;
  icgm::ProgressBar bar(static_cast<size_t>(keyframes), "keyframes");
  for (int k = 0; k < keyframes; ++k) {
    const int place = k % places;
    icgm::Keyframe kf;
    kf.stamp = icgm::Time::FromNanoseconds(k);
    const cv::Mat& src = place_descriptors[static_cast<size_t>(place)];
    for (int r = 0; r < src.rows; ++r) {
      if (u(rng) > 0.85) continue;
      cv::Mat row = src.row(r).clone();
      for (int f = 0; f < 8; ++f) {
        const int b = bit_dist(rng);
        row.at<uint8_t>(0, b / 8) ^= static_cast<uint8_t>(1u << (b % 8));
      }
      kf.descriptors.push_back(row);
      kf.keypoints.emplace_back(static_cast<float>(r), 0.f, 7.f);
      kf.points_m.emplace_back(0.0, 0.0, 2.0);
    }
    kf.relative_pose = icgm::MakePose(icgm::Vec3(0.1, 0, 0), icgm::Quat::Identity());
    // Dictionary query alone (what loop closure needs before registration).
    const double c0 = ThreadCpuMs();
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<icgm::DictionaryMatch> matches;
    builder.dictionary().Query(kf.descriptors, &matches);
    const auto t1 = std::chrono::steady_clock::now();
    query.Add(Ms(t0, t1));
    query_cpu.Add(ThreadCpuMs() - c0);
    if (k >= places) {
      ++revisits;
      recalled += (!matches.empty() && matches.front().keyframe_id % places == place) ? 1 : 0;
    }
    // Full map step: query, candidate selection, keyframe and dictionary insertion.
    icgm::KeyframeUpdate update;
    const double c2 = ThreadCpuMs();
    const auto t2 = std::chrono::steady_clock::now();
    const icgm::Status s = builder.AddKeyframe(std::move(kf), no_registration, &update);
    const auto t3 = std::chrono::steady_clock::now();
    total_cpu.Add(ThreadCpuMs() - c2);
    if (!s.ok()) {
      std::fprintf(stderr, "error: keyframe %d: %s\n", k, s.reason().c_str());
      return 1;
    }
    total.Add(Ms(t2, t3));
    insert.Add(std::max(0.0, Ms(t2, t3) - Ms(t0, t1)));
    bar.Update(static_cast<size_t>(k + 1));
  }
  bar.Finish();

  const auto& dict = builder.dictionary();
  size_t map_bytes = 0;
  for (const auto& kf : builder.map().keyframes()) {
    map_bytes += sizeof(kf) + kf.descriptors.total() * kf.descriptors.elemSize() +
                 kf.keypoints.size() * (sizeof(cv::KeyPoint) + sizeof(Eigen::Vector3d));
  }
  const size_t last = static_cast<size_t>(keyframes - std::max(1, keyframes / 10));
  std::printf("icgm_map_benchmark: %d keyframes, %d places x %d laps, %d features/place\n",
              keyframes, places, laps, features);
  std::printf("  words %d, dictionary %.1f MiB (%.1f KiB/keyframe), map %.1f KiB/keyframe\n",
              dict.num_words(), dict.MemoryBytes() / 1048576.0,
              dict.MemoryBytes() / 1024.0 / keyframes, map_bytes / 1024.0 / keyframes);
  query.Print("dictionary query, wall (all)", 0);
  query_cpu.Print("dictionary query, cpu (all)", 0);
  query.Print("dictionary query, wall (last 10%)", last);
  query_cpu.Print("dictionary query, cpu (last 10%)", last);
  insert.Print("map insert w/o query, wall (last 10%)", last);
  total.Print("AddKeyframe total, wall (last 10%)", last);
  total_cpu.Print("AddKeyframe total, cpu (last 10%)", last);
  if (revisits > 0) {
    std::printf("  revisit recall@1 %.1f %% (%d / %d)\n", 100.0 * recalled / revisits, recalled,
                revisits);
  }
  if (!save_path.empty()) {
    const auto s0 = std::chrono::steady_clock::now();
    const icgm::Status saved = icgm::SaveMap(builder.map(), save_path);
    if (!saved.ok()) {
      std::fprintf(stderr, "error: %s\n", saved.reason().c_str());
      return 1;
    }
    const auto s1 = std::chrono::steady_clock::now();
    icgm::HybridMap loaded;
    try {
      loaded = icgm::LoadMap(save_path);
    } catch (const icgm::LoadError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
    const auto s2 = std::chrono::steady_clock::now();
    icgm::MapBuilder reloaded(options);
    const icgm::Status reset = reloaded.Reset(std::move(loaded));
    const auto s3 = std::chrono::steady_clock::now();
    if (!reset.ok()) {
      std::fprintf(stderr, "error: %s\n", reset.reason().c_str());
      return 1;
    }
    std::printf(
        "  save %.0f ms, load %.0f ms, dictionary rebuild %.0f ms (%d words), file %.1f MiB\n",
        Ms(s0, s1), Ms(s1, s2), Ms(s2, s3), reloaded.dictionary().num_words(),
        std::filesystem::file_size(save_path) / 1048576.0);
  }
  return 0;
}

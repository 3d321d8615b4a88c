// icgm_place_benchmark: query time of appearance-only place recognition (core/place's
// PlaceRecognizer: weighted dictionary query, guard, temporal check, geometric verification,
// insertion) on a synthetic sequence of `--images` images driving a route `--laps` times. Each
// place is a set of 3D points with ORB-like 256-bit descriptors (per-bit biases, as real ORB
// bits are not uniform); an image sees its place from a slightly different pose (pinhole
// projection), keeps 85 % of the points with a few bits flipped, and marks `--verified` of its
// features as ICGM-verified. Prints per-image time of the query with its checks and of the
// insertion (thread CPU and wall, whole run and last 10 %), recall of the revisits and false
// loops.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/option_reader.h"
#include "core/common/progress_bar.h"
#include "core/common/thread_cpu_time.h"
#include "core/map/map_options.h"
#include "core/place/place_options.h"
#include "core/place/place_recognizer.h"
#include "tools/cli_args.h"
#include "tools/timing_series.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_place_benchmark [--images N=5000] [--features N=1000] [--laps N=2]\n"
    "                            [--verified F=0.3] [--config config/map.yaml]\n"
    "                            [--place-config config/place_recognition.yaml]\n"
    "                            [--geometry on|off] [--seed N=1]";
constexpr icgm::tools::ToolInfo kTool{"icgm_place_benchmark", kUsage};

using icgm::tools::TimingSeries;

using icgm::ThreadCpuMs;

}  // namespace

int main(int argc, char** argv) {
  int images = 0, features = 0, laps = 0;
  double verified_share = 0.0;
  unsigned seed = 1;
  icgm::MapBuilderOptions map_options;
  icgm::PlaceRecognitionOptions place;
  try {
    const icgm::tools::CliArgs args(
        argc, argv,
        {"images", "features", "laps", "verified", "config", "place-config", "geometry", "seed"},
        {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (!args.positional().empty()) {
      throw std::invalid_argument("unexpected argument '" + args.positional().front() + "'");
    }
    images = args.GetInt("images", 5000);
    features = args.GetInt("features", 1000);
    laps = args.GetInt("laps", 2);
    verified_share = args.GetDouble("verified", 0.3);
    seed = static_cast<unsigned>(args.GetInt("seed", 1));
    if (images < 1 || features < 1 || laps < 1) {
      throw std::invalid_argument("--images, --features and --laps must be >= 1");
    }
    if (!(verified_share >= 0.0 && verified_share <= 1.0)) {
      throw std::invalid_argument("--verified must be in [0, 1]");
    }
    if (args.Has("config")) {
      icgm::ReadOptions(icgm::OptionReader::FromFile(args.Get("config")), &map_options);
    }
    if (args.Has("place-config")) {
      icgm::ReadPlaceRecognitionFile(icgm::OptionReader::FromFile(args.Get("place-config")),
                                     &place);
    }
    const std::string geometry = args.Get("geometry", place.geometry.enabled ? "on" : "off");
    if (geometry != "on" && geometry != "off") {
      throw std::invalid_argument("--geometry must be on or off");
    }
    place.geometry.enabled = geometry == "on";
  } catch (const icgm::LoadError& e) {
    return icgm::tools::Failure(kTool, e.what());
  } catch (const std::invalid_argument& e) {
    return icgm::tools::UsageError(kTool, e.what());
  }
  map_options.dictionary.descriptor_type = icgm::DescriptorType::kBinary;

  const int places = std::max(1, images / laps);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> bias(256);
  for (double& b : bias) b = 0.25 + 0.5 * u(rng);
  // Places: points in front of the camera, one descriptor each.
  std::vector<std::vector<Eigen::Vector3d>> points(static_cast<size_t>(places));
  std::vector<cv::Mat> descriptors(static_cast<size_t>(places));
  for (int p = 0; p < places; ++p) {
    descriptors[p] = cv::Mat::zeros(features, 32, CV_8U);
    for (int r = 0; r < features; ++r) {
      points[p].emplace_back(-3.0 + 6.0 * u(rng), -1.5 + 3.0 * u(rng), 2.0 + 6.0 * u(rng));
      uint8_t* d = descriptors[p].ptr<uint8_t>(r);
      for (int bit = 0; bit < 256; ++bit) {
        if (u(rng) < bias[bit]) d[bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
      }
    }
  }
  const icgm::CameraIntrinsics camera;
  std::uniform_int_distribution<int> bit_dist(0, 255);
  std::normal_distribution<double> pixel_noise(0.0, 0.5);

  icgm::PlaceRecognizer recognizer(place, map_options.dictionary, camera);
  TimingSeries cpu, wall, insert_cpu;
  int revisits = 0, recalled = 0, false_loops = 0;
  icgm::ProgressBar bar(static_cast<size_t>(images), "images");
  for (int k = 0; k < images; ++k) {
    const int p = k % places;
    const double offset_m = 0.2 * (u(rng) - 0.5);
    icgm::FeatureSet f;
    std::vector<uint8_t> verified;
    for (int r = 0; r < features; ++r) {
      if (u(rng) > 0.85) continue;
      const Eigen::Vector3d x = points[p][r] - Eigen::Vector3d(offset_m, 0.0, 0.0);
      const double px = camera.fx_px * x.x() / x.z() + camera.cx_px + pixel_noise(rng);
      const double py = camera.fy_px * x.y() / x.z() + camera.cy_px + pixel_noise(rng);
      if (px < 0 || py < 0 || px >= camera.width_px || py >= camera.height_px) continue;
      cv::Mat row = descriptors[p].row(r).clone();
      for (int b = 0; b < 8; ++b) {
        const int n = bit_dist(rng);
        row.at<uint8_t>(0, n / 8) ^= static_cast<uint8_t>(1u << (n % 8));
      }
      f.keypoints.emplace_back(static_cast<float>(px), static_cast<float>(py), 7.f);
      f.descriptors.push_back(row);
      verified.push_back(u(rng) < verified_share ? 1 : 0);
    }
    icgm::PlaceDecision d;
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = ThreadCpuMs();
    icgm::Status s = recognizer.Recognize(k, f, verified, &d);
    const double c1 = ThreadCpuMs();
    cpu.Add(c1 - c0);
    wall.Add(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (s.ok()) s = recognizer.Add();
    insert_cpu.Add(ThreadCpuMs() - c1);
    if (!s.ok()) return icgm::tools::Failure(kTool, s.reason());
    const bool revisit = k >= places;
    revisits += revisit ? 1 : 0;
    if (d.match >= 0) {
      if (d.match % places == p) {
        recalled += 1;
      } else {
        false_loops += 1;
      }
    }
    bar.Update(static_cast<size_t>(k + 1));
  }
  bar.Finish();
  const size_t last = wall.ms.size() - std::max<size_t>(1, wall.ms.size() / 10);
  std::printf("%d images (%d places x %d laps), ~%.0f features each, %.0f%% verified; %d words\n",
              images, places, laps, 0.85 * features * 0.9, 100.0 * verified_share,
              recognizer.dictionary().num_words());
  std::printf("geometric verification %s, temporal consistency %d queries\n",
              place.geometry.enabled ? "on" : "off", place.temporal.consistent_queries);
  cpu.Print("query + checks, cpu (all)", 0);
  cpu.Print("query + checks, cpu (last 10%)", last);
  wall.Print("query + checks, wall (all)", 0);
  wall.Print("query + checks, wall (last 10%)", last);
  insert_cpu.Print("insertion, cpu (all)", 0);
  insert_cpu.Print("insertion, cpu (last 10%)", last);
  std::printf("  revisits recognized %d of %d, false loops %d\n", recalled, revisits, false_loops);
  return 0;
}

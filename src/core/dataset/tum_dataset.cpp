#include "core/dataset/tum_dataset.h"

#include <algorithm>
#include <cassert>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "core/common/status.h"
#include "core/dataset/depth_image.h"
#include "core/dataset/stamp_association.h"
#include "core/dataset/text_table.h"

namespace icgm {

namespace {

namespace fs = std::filesystem;

struct StampedFile {
  Time stamp;
  std::string path;
};

// Reads "timestamp path" lines; paths are resolved against the dataset folder.
std::vector<StampedFile> ReadIndex(const fs::path& dir, const std::string& name) {
  const fs::path file = dir / name;
  if (!fs::is_regular_file(file)) {
    throw LoadError("TUM dataset '" + dir.string() + "' has no " + name);
  }
  std::vector<StampedFile> out;
  for (const TextRow& row : ReadTextTable(file.string())) {
    const std::string where = file.string() + ":" + std::to_string(row.line_number) + ": ";
    if (row.fields.size() != 2) {
      throw LoadError(where + "expected 'timestamp path', got " +
                      std::to_string(row.fields.size()) + " fields");
    }
    StampedFile sf;
    if (!Time::Parse(row.fields[0], &sf.stamp)) {
      throw LoadError(where + "bad timestamp '" + row.fields[0] + "'");
    }
    const fs::path image = dir / row.fields[1];
    if (!fs::is_regular_file(image)) {
      throw LoadError(where + "listed image '" + image.string() + "' does not exist");
    }
    sf.path = image.string();
    out.push_back(std::move(sf));
  }
  std::sort(out.begin(), out.end(),
            [](const StampedFile& a, const StampedFile& b) { return a.stamp < b.stamp; });
  return out;
}

// Images must match the intrinsics they will be projected with.
void CheckSize(const cv::Mat& image, const std::string& path, const CameraIntrinsics& k) {
  if (image.cols != k.width_px || image.rows != k.height_px) {
    throw LoadError("image '" + path + "' is " + std::to_string(image.cols) + "x" +
                    std::to_string(image.rows) + " but the intrinsics are " +
                    std::to_string(k.width_px) + "x" + std::to_string(k.height_px));
  }
}

}  // namespace

TumDataset TumDataset::Open(const std::string& dir, const CameraIntrinsics& intrinsics,
                            double max_association_dt_s) {
  if (!fs::is_directory(dir)) throw LoadError("TUM dataset folder '" + dir + "' does not exist");
  if (!intrinsics.Valid()) throw LoadError("TUM dataset '" + dir + "': invalid intrinsics");
  if (!(max_association_dt_s >= 0.0)) {
    throw LoadError("TUM dataset: max association dt must be >= 0 s");
  }
  const std::vector<StampedFile> rgb = ReadIndex(dir, "rgb.txt");
  const std::vector<StampedFile> depth = ReadIndex(dir, "depth.txt");

  std::vector<Time> rgb_stamps, depth_stamps;
  for (const StampedFile& f : rgb) rgb_stamps.push_back(f.stamp);
  for (const StampedFile& f : depth) depth_stamps.push_back(f.stamp);
  const auto pairs = AssociateStamps(rgb_stamps, depth_stamps, max_association_dt_s);

  TumDataset ds;
  ds.dir_ = dir;
  ds.intrinsics_ = intrinsics;
  for (const auto& [i, j] : pairs) {
    ds.frames_.push_back({rgb[i].stamp, depth[j].stamp, rgb[i].path, depth[j].path});
  }
  ds.unmatched_rgb_ = rgb.size() - pairs.size();
  const fs::path gt = fs::path(dir) / "groundtruth.txt";
  if (fs::exists(gt)) {
    ds.groundtruth_ = ReadTumTrajectory(gt.string());
    SortByStamp(&ds.groundtruth_);
  }
  return ds;
}

const RgbdFrameRef& TumDataset::frame(size_t i) const {
  assert(i < frames_.size());
  return frames_[i];
}

cv::Mat TumDataset::LoadBgr(size_t i) const {
  const std::string& path = frame(i).rgb_path;
  cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) throw LoadError("cannot read colour image '" + path + "'");
  CheckSize(img, path, intrinsics_);
  return img;
}

cv::Mat TumDataset::LoadDepthM(size_t i) const {
  const std::string& path = frame(i).depth_path;
  const cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (raw.empty()) throw LoadError("cannot read depth image '" + path + "'");
  cv::Mat depth = ToMetricDepth(raw, intrinsics_.depth_scale);
  if (depth.empty()) {
    throw LoadError("depth image '" + path + "' is not 16-bit or float single channel");
  }
  CheckSize(depth, path, intrinsics_);
  return depth;
}

}  // namespace icgm

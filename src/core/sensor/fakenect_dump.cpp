#include "core/sensor/fakenect_dump.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/sensor/kinect_disparity.h"

namespace icgm {
namespace {

std::string FileName(const FakenectFrame& f) {
  char name[96];
  std::snprintf(name, sizeof(name), "%c-%.6f-%u.%s", f.color ? 'r' : 'd', f.record_time_s,
                f.timestamp, f.color ? "ppm" : "pgm");
  return name;
}

Status WriteFrame(const std::string& path, const FakenectFrame& f) {
  std::ofstream out(path, std::ios::binary);
  out << (f.color ? "P6 " : "P5 ") << f.image.cols << " " << f.image.rows << " "
      << (f.color ? 255 : 65535) << "\n";
  const size_t row_bytes = f.image.cols * f.image.elemSize();
  for (int y = 0; y < f.image.rows; ++y) {
    out.write(reinterpret_cast<const char*>(f.image.ptr(y)), row_bytes);
  }
  return out ? Status::Ok() : Status::Error("cannot write '" + path + "'");
}

}  // namespace

Status WriteFakenectDump(VirtualFrameSource* source, int max_frames, const std::string& dir,
                         const std::function<void(size_t, size_t)>& progress) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::Error("cannot create '" + dir + "': " + ec.message());
  const auto wanted = [&](const FrameEvent& e) {
    return max_frames <= 0 || e.frame < static_cast<size_t>(max_frames);
  };
  size_t total = 0, written = 0;
  for (const FrameEvent& e : source->events()) total += wanted(e);
  std::ostringstream index;
  for (const FrameEvent& e : source->events()) {
    if (!wanted(e)) continue;
    std::string error;
    const cv::Mat image = source->Load(e, &error);
    if (image.empty()) return Status::Error("frame " + std::to_string(e.frame) + ": " + error);
    FakenectFrame f;
    f.color = e.color;
    f.record_time_s = 1.0 + e.device_us * 1e-6;
    f.timestamp = static_cast<uint32_t>(e.device_us * kKinectTicksPerUs);  // wraps as the Kinect's
    if (e.color) {
      f.image = image;  // RGB
    } else {
      f.image.create(image.size(), CV_16UC1);
      for (int y = 0; y < image.rows; ++y) {
        const uint16_t* mm = image.ptr<uint16_t>(y);
        uint16_t* raw = f.image.ptr<uint16_t>(y);
        for (int x = 0; x < image.cols; ++x) raw[x] = KinectMmToRaw(mm[x]);
      }
    }
    const std::string name = FileName(f);
    if (Status s = WriteFrame(dir + "/" + name, f); !s.ok()) return s;
    index << name << "\n";
    if (progress) progress(++written, total);
  }
  const std::string tmp = dir + "/INDEX.txt.tmp";
  {
    std::ofstream out(tmp);
    out << index.str();
    if (!out) return Status::Error("cannot write '" + tmp + "'");
  }
  std::filesystem::rename(tmp, dir + "/INDEX.txt", ec);
  if (ec) return Status::Error("cannot write '" + dir + "/INDEX.txt': " + ec.message());
  return Status::Ok();
}

Status ReadFakenectDump(const std::string& dir, std::vector<FakenectFrame>* out) {
  out->clear();
  std::ifstream index(dir + "/INDEX.txt");
  if (!index) return Status::Error("cannot read '" + dir + "/INDEX.txt'");
  std::string line;
  while (std::getline(index, line)) {
    if (line.empty()) continue;
    FakenectFrame f;
    char type = 0;
    // The file name as fakenect parses it.
    if (std::sscanf(line.c_str(), "%c-%lf-%u", &type, &f.record_time_s, &f.timestamp) != 3) {
      return Status::Error("INDEX.txt: bad line '" + line + "'");
    }
    if (type != 'r' && type != 'd') continue;  // accelerometer
    f.color = type == 'r';
    const std::string path = dir + "/" + line;
    std::ifstream in(path, std::ios::binary);
    std::string magic;
    int width = 0, height = 0, max_value = 0;
    in >> magic >> width >> height >> max_value;
    in.get();  // the header's newline
    if (!in || magic != (f.color ? "P6" : "P5") || width < 1 || height < 1) {
      return Status::Error("'" + path + "': not a fakenect frame");
    }
    f.image.create(height, width, f.color ? CV_8UC3 : CV_16UC1);
    in.read(reinterpret_cast<char*>(f.image.data), f.image.total() * f.image.elemSize());
    if (!in) return Status::Error("'" + path + "': truncated");
    out->push_back(std::move(f));
  }
  return Status::Ok();
}

}  // namespace icgm

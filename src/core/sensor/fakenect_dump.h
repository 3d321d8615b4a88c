// A fakenect dump: the folder libfreenect's fakenect library replays as a Kinect v1 when a
// program runs with FAKENECT_PATH=<folder> and fakenect's libfreenect first on its library path
// (Debian: /usr/lib/<arch>/fakenect, or the `fakenect` wrapper script of libfreenect-bin).
// Layout, as fakenect reads it: INDEX.txt lists one file per line, in playback order, named
// "<type>-<record time s>-<device timestamp>.<ext>": type 'r' a colour frame (binary PPM header
// "P6 640 480 255" on one line, then RGB888 rows), 'd' a depth frame (header "P5 640 480 65535"
// on one line, then the raw 11-bit values as native-endian uint16 rows, as libfreenect's
// FREENECT_DEPTH_11BIT mode delivers them; core/sensor/kinect_disparity.h). fakenect sleeps by
// the record-time differences between lines and hands each frame's device timestamp (the
// Kinect's 60 MHz clock, 32 bits) to the frame callback.
//
// WriteFakenectDump makes such a folder from the frames of a virtual frame source (a simulated
// scenario or a TUM folder; virtual_frame_source.h), each frame at its device time; the depth is
// the source's, in the colour camera's view (both sources deliver registered depth).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/status.h"
#include "core/sensor/virtual_frame_source.h"

namespace icgm {

// Ticks of the Kinect's frame clock per microsecond (60 MHz).
inline constexpr uint64_t kKinectTicksPerUs = 60;

struct FakenectFrame {
  bool color = true;
  double record_time_s = 0.0;
  uint32_t timestamp = 0;  // 60 MHz device ticks
  cv::Mat image;           // colour: CV_8UC3 RGB; depth: CV_16UC1 raw 11-bit values
};

// Writes the source's first `max_frames` frames (0 = all) to `dir` (created if missing);
// INDEX.txt is written last, so a reader never sees a partial index. Fails naming the file.
// `progress` (optional) is told the images written and the total after each one.
Status WriteFakenectDump(VirtualFrameSource* source, int max_frames, const std::string& dir,
                         const std::function<void(size_t, size_t)>& progress = {});

// Reads a dump back as fakenect plays it (INDEX.txt order; accelerometer lines skipped).
Status ReadFakenectDump(const std::string& dir, std::vector<FakenectFrame>* out);

}  // namespace icgm

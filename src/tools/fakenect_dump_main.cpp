// Writes a fakenect dump (core/sensor/fakenect_dump.h) from a simulated scenario or a TUM folder,
// for running the Kinect v1 driver, or any libfreenect program, without a Kinect.
#include <cstdio>
#include <memory>

#include "core/common/progress_bar.h"
#include "core/sensor/fakenect_dump.h"
#include "core/sensor/virtual_device_uri.h"
#include "tools/cli_args.h"

namespace {

const icgm::tools::ToolInfo kTool{
    "icgm_fakenect_dump",
    "usage: icgm_fakenect_dump --source URI --out DIR [--frames N]\n"
    "  Writes the frames of a virtual-device source (icgm-virtual://sim?scenario=config/sim/x.yaml\n"
    "  or icgm-virtual://tum?dir=/path/to/tum_folder) to DIR as a fakenect dump: INDEX.txt and\n"
    "  one PPM (colour) / PGM (raw 11-bit depth) per frame, on the source's device times.\n"
    "  --frames: the first N frames only (default: all). Play it with libfreenect's fakenect:\n"
    "    FAKENECT_PATH=DIR LD_LIBRARY_PATH=/usr/lib/<arch>/fakenect <program using freenect://0>\n"};

}  // namespace

int main(int argc, char** argv) {
  using namespace icgm;
  std::string uri, out;
  int frames = 0;
  try {
    const tools::CliArgs args(argc, argv, {"source", "out", "frames"}, {});
    if (args.help()) return tools::PrintUsage(kTool);
    uri = args.Require("source");
    out = args.Require("out");
    frames = args.GetInt("frames", 0);
    if (frames < 0) throw std::invalid_argument("--frames must be >= 0");
  } catch (const std::invalid_argument& e) {
    return tools::UsageError(kTool, e.what());
  }
  VirtualDeviceConfig config;
  if (Status s = ParseVirtualDeviceUri(uri, &config); !s.ok()) return tools::UsageError(kTool, s.reason());
  std::unique_ptr<VirtualFrameSource> source;
  if (Status s = OpenVirtualFrameSource(config, &source); !s.ok()) return tools::Failure(kTool, s.reason());
  std::unique_ptr<ProgressBar> bar;
  const Status written = WriteFakenectDump(source.get(), frames, out, [&](size_t done, size_t total) {
    if (!bar) bar = std::make_unique<ProgressBar>(total, "images");
    bar->Update(done);
  });
  if (bar) bar->Finish();
  if (!written.ok()) return tools::Failure(kTool, written.reason());
  std::printf("fakenect dump written to %s\n", out.c_str());
  return 0;
}

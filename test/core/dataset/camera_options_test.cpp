#include "core/dataset/camera_options.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "core/common/status.h"
#include "temp_dir.h"

namespace icgm {
namespace {

TEST(CameraOptionsTest, ReadsAllFields) {
  const OptionReader root = OptionReader::FromString(
      "camera: {fx_px: 517.3, fy_px: 516.5, cx_px: 318.6, cy_px: 255.3, width_px: 320, "
      "height_px: 240, depth_scale: 5000, depth_time_offset_s: -0.02, depth_correction: 1.02, "
      "readout_s: 0.025, first_row_offset_s: -0.0125}");
  const OptionReader section = root.Section("camera");
  CameraIntrinsics k;
  ReadOptions(section, &k);
  EXPECT_DOUBLE_EQ(k.fx_px, 517.3);
  EXPECT_DOUBLE_EQ(k.fy_px, 516.5);
  EXPECT_DOUBLE_EQ(k.cx_px, 318.6);
  EXPECT_DOUBLE_EQ(k.cy_px, 255.3);
  EXPECT_EQ(k.width_px, 320);
  EXPECT_EQ(k.height_px, 240);
  EXPECT_DOUBLE_EQ(k.depth_scale, 5000.0);
  EXPECT_DOUBLE_EQ(k.depth_time_offset_s, -0.02);
  EXPECT_DOUBLE_EQ(k.depth_correction, 1.02);
  EXPECT_DOUBLE_EQ(k.readout_s, 0.025);
  EXPECT_DOUBLE_EQ(k.first_row_offset_s, -0.0125);
  EXPECT_TRUE(section.UnusedKeys().empty());
}

TEST(CameraOptionsTest, MissingKeysKeepDefaults) {
  CameraIntrinsics k;
  ReadOptions(OptionReader::FromString("camera: {fx_px: 600}").Section("camera"), &k);
  EXPECT_DOUBLE_EQ(k.fx_px, 600.0);
  EXPECT_DOUBLE_EQ(k.fy_px, CameraIntrinsics().fy_px);
  EXPECT_DOUBLE_EQ(k.depth_correction, 1.0);
  EXPECT_DOUBLE_EQ(k.readout_s, 0.0);  // global shutter unless configured
}

TEST(CameraOptionsTest, RejectsBadValues) {
  for (const char* text :
       {"camera: {fx_px: 0}", "camera: {fy_px: -3}", "camera: {width_px: 0}",
        "camera: {height_px: 1.5}", "camera: {depth_scale: 0}", "camera: {cx_px: abc}",
        "camera: {depth_correction: 0}", "camera: {depth_correction: 3}",
        "camera: {readout_s: -0.01}", "camera: {readout_s: 2}",
        "camera: {first_row_offset_s: 1.5}"}) {
    CameraIntrinsics k;
    EXPECT_THROW(ReadOptions(OptionReader::FromString(text).Section("camera"), &k), LoadError)
        << text;
  }
}

TEST(CameraOptionsTest, DepthCorrectionRangeIsEnforcedByTheReader) {
  // Node parameters go through the same reader (nodelets/sensor_calibration.h).
  const auto read = [](double value) {
    CameraIntrinsics k;
    ReadOptions(
        OptionReader::FromString("camera: {depth_correction: " + std::to_string(value) + "}")
            .Section("camera"),
        &k);
    return k;
  };
  for (const double ok : {0.5, 1.0, 1.035, 2.0}) {
    EXPECT_NO_THROW(read(ok)) << ok;
  }
  for (const double bad : {0.0, -1.0, 0.49, 2.01, std::nan("")}) {
    try {
      read(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find("depth_correction"), std::string::npos) << e.what();
    }
  }
}

TEST(CameraOptionsTest, LoadFromFile) {
  testing::TempDir dir;
  const CameraIntrinsics k = LoadCameraIntrinsics(
      dir.Write("cam.yaml",
                "camera:\n  fx_px: 400\n  fy_px: 401\n  cx_px: 320\n  cy_px: 240\n"
                "  width_px: 640\n  height_px: 480\n  depth_scale: 1000\n"
                "  distortion_k1: 0.04\n  distortion_p2: -0.0001\n"));
  EXPECT_DOUBLE_EQ(k.fx_px, 400.0);
  EXPECT_DOUBLE_EQ(k.depth_scale, 1000.0);
  EXPECT_DOUBLE_EQ(k.distortion_k1, 0.04);
  EXPECT_DOUBLE_EQ(k.distortion_p2, -0.0001);
  EXPECT_TRUE(k.HasDistortion());
  // A required intrinsic missing is an error naming it, never a default (fx 525).
  try {
    LoadCameraIntrinsics(dir.Write("nofx.yaml",
                                   "camera: {fy_px: 400, cx_px: 320, cy_px: 240, width_px: 640, "
                                   "height_px: 480, depth_scale: 1000}\n"));
    ADD_FAILURE() << "a camera file without fx_px was accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("fx_px"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LoadCameraIntrinsics(dir.Write("typo.yaml", "camera: {fx: 400}\n")), LoadError);
  // A top-level section other than `camera` and `depth_camera` is a typo, named in the error.
  try {
    LoadCameraIntrinsics(dir.Write("other.yaml",
                                   "camera: {fx_px: 400, fy_px: 400, cx_px: 320, cy_px: 240, "
                                   "width_px: 640, height_px: 480, depth_scale: 1000}\n"
                                   "other: {a: 1}\n"));
    ADD_FAILURE() << "a camera file with an unknown top-level section was accepted";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("other"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LoadCameraIntrinsics(dir.Write("none.yaml", "icgm: {a: 1}\n")), LoadError);
  // A typo or bad value inside `depth_camera` is refused by every reader of the file, also by
  // those that only use `camera` (the offline tools), naming the file and the key.
  const std::string colour =
      "camera: {fx_px: 400, fy_px: 400, cx_px: 320, cy_px: 240, width_px: 640, height_px: 480, "
      "depth_scale: 1000}\n";
  const std::string depth = "depth_camera: {fx_px: 575, fy_px: 575, cx_px: 320, cy_px: 240, "
                            "width_px: 640, height_px: 480, ";
  EXPECT_DOUBLE_EQ(
      LoadCameraIntrinsics(dir.Write("good.yaml", colour + depth + "x_m: -0.025}\n")).fx_px, 400.0);
  for (const auto& [name, tail, key] :
       {std::tuple<const char*, const char*, const char*>{"xm.yaml", "xm: -0.025}", "depth_camera.xm"},
        {"range.yaml", "x_m: 25}", "x_m"},
        {"type.yaml", "yaw_deg: left}", "yaw_deg"}}) {
    const std::string path = dir.Write(name, colour + depth + tail + "\n");
    try {
      LoadCameraIntrinsics(path);
      ADD_FAILURE() << name << ": a bad depth_camera section was accepted";
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  // A depth camera section lacking an intrinsic is refused too.
  EXPECT_THROW(LoadCameraIntrinsics(dir.Write("nofx_depth.yaml",
                                              colour + "depth_camera: {fy_px: 575}\n")),
               LoadError);
  EXPECT_THROW(LoadCameraIntrinsics(dir.File("missing.yaml")), LoadError);
}

TEST(CameraOptionsTest, ShippedTumConfigMatchesBenchmarkCalibration) {
  // TUM fr1 calibration published with the benchmark (registered depth, 5000 per metre).
  const CameraIntrinsics k =
      LoadCameraIntrinsics(std::string(ICGM_SOURCE_DIR) + "/config/camera/tum_fr1.yaml");
  EXPECT_DOUBLE_EQ(k.fx_px, 517.3);
  EXPECT_DOUBLE_EQ(k.fy_px, 516.5);
  EXPECT_DOUBLE_EQ(k.cx_px, 318.6);
  EXPECT_DOUBLE_EQ(k.cy_px, 255.3);
  EXPECT_EQ(k.width_px, 640);
  EXPECT_EQ(k.height_px, 480);
  EXPECT_DOUBLE_EQ(k.depth_scale, 5000.0);
  EXPECT_DOUBLE_EQ(k.depth_correction, 1.035);  // the benchmark's ds for Freiburg 1
  // Rolling shutter: rows read out within one frame period of the 30 Hz stream, the stamp at
  // the middle row.
  EXPECT_GT(k.readout_s, 0.0);
  EXPECT_LT(k.readout_s, 1.0 / 30.0);
  EXPECT_DOUBLE_EQ(k.first_row_offset_s, -0.5 * k.readout_s);
}

}  // namespace
}  // namespace icgm

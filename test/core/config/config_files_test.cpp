// Loads every shipped configuration file (config/**/*.yaml) and reads each top-level section
// with the options reader that owns it, so a typo, a wrong type, an out-of-range value or a
// section nobody reads fails here rather than at run time.
//
// To register a new section, add one line to SectionReaders(), e.g.
//   {"loop_closure", Reads<LoopClosureOptions>()},
// and the module that defines its ReadOptions to the DEPS of the `config` test in
// src/core/dataset/module.cmake.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/option_reader.h"
#include "core/common/status.h"
#include "core/dataset/camera_options.h"
#include "core/features/descriptor_matcher.h"
#include "core/features/feature_extractor.h"
#include "core/icgm/icgm_matcher.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/map_export_options.h"
#include "core/map/map_options.h"
#include "core/mono/mono_options.h"
#include "core/nav/navigation_options.h"
#include "core/place/place_options.h"
#include "core/odometry/frontend_types.h"
#include "core/odometry/odometry_fusion.h"
#include "core/odometry/wheel_odometry_buffer.h"
#include "core/registration/dense_refinement.h"
#include "core/registration/depth_consistency.h"
#include "core/registration/rgbd_registration.h"
#include "core/sensor/depth_registration.h"
#include "core/sensor/robot_options.h"
#include "core/sim/sim_options.h"
#include "core/slam/keyframe_registration.h"
#include "core/slam/map_refinement.h"
#include "core/slam/slam_options.h"

namespace icgm {
namespace {

using SectionReader = std::function<void(const OptionReader&)>;

// Top-level section name -> reads the section into its options struct (throws LoadError on a
// bad value). Keys of the section that the reader does not ask for are reported as unknown.
// Reads one section into a default-constructed options struct T.
template <typename T>
SectionReader Reads() {
  return [](const OptionReader& section) {
    T options;
    ReadOptions(section, &options);
  };
}

// A section of config/navigation.yaml: ReadNavigationOptions takes the file root, so the values
// are checked through a root holding only this section (which also rejects its unknown keys),
// and the section's keys are marked known here.
SectionReader ReadsNavigationSection(const std::string& name) {
  return [name](const OptionReader& section) {
    YAML::Node root;
    root[name] = section.node();
    NavigationOptions options;
    ReadNavigationOptions(OptionReader(root, ""), &options);
    for (const auto& kv : section.node()) {
      std::string value;  // every value is a scalar: read as text only to mark the key known
      section.Read(kv.first.as<std::string>(), &value);
    }
  };
}

const std::map<std::string, SectionReader>& SectionReaders() {
  static const std::map<std::string, SectionReader> readers = {
      {"camera", Reads<CameraIntrinsics>()},
      {"depth_camera", Reads<DepthCameraCalibration>()},
      {"robot", Reads<RobotOptions>()},
      {"features", Reads<FeatureOptions>()},
      {"matcher", Reads<MatcherOptions>()},
      {"icgm", Reads<IcgmOptions>()},
      {"tracker",
       [](const OptionReader& section) {
         // The tracker reader takes the file root (it also reads features/matcher/icgm), so
         // values are checked through a root holding only this section, and its two keys are
         // marked as known here.
         YAML::Node root;
         root["tracker"] = section.node();
         TrackerOptions options;
         ReadOptions(OptionReader(root, ""), &options);
         std::string mode;
         int window_size = 0;
         section.Read("mode", &mode);
         section.Read("window_size", &window_size, 0, 1 << 30);
       }},
      {"registration", Reads<RegistrationOptions>()},
      {"frontend", Reads<FrontendOptions>()},
      {"fusion", Reads<FusionOptions>()},
      {"wheel_odometry", Reads<WheelOdometryOptions>()},
      {"depth_consistency", Reads<DepthConsistencyOptions>()},
      {"dense_refinement", Reads<DenseRefinementOptions>()},
      {"dictionary", Reads<DictionaryOptions>()},
      {"loop_closure", Reads<LoopClosureOptions>()},
      {"map", Reads<MapOptions>()},
      {"pose_graph", Reads<PoseGraphOptions>()},
      {"sim", Reads<sim::SimOptions>()},
      {"place_recognition", Reads<PlaceRecognitionOptions>()},
      {"temporal_consistency", Reads<TemporalConsistencyOptions>()},
      {"geometric_verification", Reads<GeometricVerificationOptions>()},
      {"keyframe_registration", Reads<LoopRegistrationOptions>()},
      {"map_refinement", Reads<MapRefinementOptions>()},
      {"bundle_adjustment", Reads<BundleAdjustmentOptions>()},
      {"mono", Reads<MonoVoOptions>()},
      {"map_cloud", Reads<MapCloudOptions>()},
      {"static_points", Reads<StaticPointOptions>()},
      {"occupancy_grid", Reads<OccupancyGridOptions>()},
      {"navigator", ReadsNavigationSection("navigator")},
      {"obstacle_grid", ReadsNavigationSection("obstacle_grid")},
      {"local_planner", ReadsNavigationSection("local_planner")},
      {"controller", ReadsNavigationSection("controller")},
      {"walker_tracker", ReadsNavigationSection("walker_tracker")},
      {"crowd_guard", ReadsNavigationSection("crowd_guard")},
      {"localization",
       [](const OptionReader& section) {
         // Read by ReadMapSlamOptions through ReadLocalizationOptions, which also marks the
         // section's keys known here.
         LocalizationOptions options;
         ReadLocalizationOptions(section, &options);
       }},
      {"map_features",
       [](const OptionReader& section) {
         // Read by ReadMapSlamOptions from the file root: checked through a root holding only
         // this section (which also rejects its unknown keys); its key is marked known here.
         YAML::Node root;
         root["map_features"] = section.node();
         SlamOptions options;
         ReadMapSlamOptions(OptionReader(root, ""), &options);
         std::string source = NameOf(options.map_features.source);
         section.Read("source", &source);
       }},
  };
  return readers;
}

// Problems found in one parsed file; empty when it is fine.
std::vector<std::string> CheckConfig(const OptionReader& root) {
  std::vector<std::string> problems;
  if (!root.node().IsMap() || root.node().size() == 0) {
    problems.push_back("top level must be a non-empty mapping of sections");
    return problems;
  }
  for (const auto& kv : root.node()) {
    const std::string name = kv.first.as<std::string>();
    const auto it = SectionReaders().find(name);
    if (it == SectionReaders().end()) {
      problems.push_back("unknown top-level section '" + name + "'");
      continue;
    }
    try {
      const OptionReader section = root.Section(name);
      it->second(section);
      for (const std::string& key : section.UnusedKeys()) {
        problems.push_back("unknown key '" + key + "'");
      }
    } catch (const LoadError& e) {
      problems.push_back(e.what());
    }
  }
  return problems;
}

std::vector<std::string> ShippedConfigFiles() {
  std::vector<std::string> files;
  const std::filesystem::path root = std::filesystem::path(ICGM_SOURCE_DIR) / "config";
  if (!std::filesystem::is_directory(root)) return files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (entry.is_regular_file() && entry.path().extension() == ".yaml") {
      files.push_back(std::filesystem::relative(entry.path(), ICGM_SOURCE_DIR).string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string Join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += "\n  " + s;
  return out;
}

class ConfigFileTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ConfigFileTest, ParsesAndEverySectionIsKnown) {
  const std::string path = std::string(ICGM_SOURCE_DIR) + "/" + GetParam();
  std::vector<std::string> problems;
  try {
    problems = CheckConfig(OptionReader::FromFile(path));
  } catch (const LoadError& e) {
    problems.push_back(e.what());
  }
  EXPECT_TRUE(problems.empty()) << GetParam() << ":" << Join(problems);
}

INSTANTIATE_TEST_SUITE_P(Shipped, ConfigFileTest, ::testing::ValuesIn(ShippedConfigFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(ConfigFilesTest, FindsTheCameraConfigs) {
  const auto files = ShippedConfigFiles();
  for (const char* expected : {"config/camera/tum_fr1.yaml", "config/camera/kinect_default.yaml"}) {
    EXPECT_NE(std::find(files.begin(), files.end(), expected), files.end()) << expected;
  }
}

// The checker itself must reject what it is meant to catch.
TEST(ConfigFilesTest, CheckerRejectsBadFiles) {
  EXPECT_TRUE(CheckConfig(OptionReader::FromString("camera: {fx_px: 500}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("camera: {fx: 500}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("camera: {fx_px: -1}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("camera: {fx_px: abc}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("camra: {fx_px: 500}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("")).empty());
  EXPECT_TRUE(CheckConfig(OptionReader::FromString("localization: {keyframes: session}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("localization: {keyframe: none}")).empty());
  EXPECT_FALSE(CheckConfig(OptionReader::FromString("localization: {keyframes: all}")).empty());
}

// The loaders the tools call reject a misspelt top-level key of a whole file, naming it, as
// every section rejects its own (camera files: `camera` and `depth_camera` only).
TEST(ConfigFilesTest, FileLoadersRejectAMisspeltTopLevelKey) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("icgm_config_top_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto with_typo = [&](const std::string& shipped, const std::string& line) {
    const fs::path out = dir / fs::path(shipped).filename();
    fs::copy_file(fs::path(ICGM_SOURCE_DIR) / shipped, out, fs::copy_options::overwrite_existing);
    std::ofstream(out, std::ios::app) << "\n" << line << "\n";
    return out.string();
  };
  const auto expect_named = [](const std::function<void()>& load, const std::string& key) {
    try {
      load();
      ADD_FAILURE() << "accepted unknown top-level key " << key;
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  // The shipped files themselves load through the same loaders.
  const std::string shipped = std::string(ICGM_SOURCE_DIR) + "/";
  EXPECT_NO_THROW(LoadCameraIntrinsics(shipped + "config/camera/kinect_default.yaml"));
  EXPECT_NO_THROW(sim::LoadSimOptions(shipped + "config/sim/static_short.yaml"));
  const std::string camera = with_typo("config/camera/kinect_default.yaml", "depth_camra: {}");
  expect_named([&] { LoadCameraIntrinsics(camera); }, "depth_camra");
  const std::string scenario = with_typo("config/sim/static_short.yaml", "crowd: {count: 3}");
  expect_named([&] { sim::LoadSimOptions(scenario); }, "crowd");
  const std::string place =
      with_typo("config/place_recognition.yaml", "temporal_consistancy: {continuation: false}");
  expect_named(
      [&] {
        PlaceRecognitionOptions o;
        ReadPlaceRecognitionFile(OptionReader::FromFile(place), &o);
      },
      "temporal_consistancy");
  fs::remove_all(dir);
}

// Every argument of the shipped launch files says what it does (roslaunch --ros-args prints it).
TEST(ConfigFilesTest, EveryLaunchArgumentIsDocumented) {
  namespace fs = std::filesystem;
  size_t launch_files = 0, args = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(ICGM_SOURCE_DIR) / "launch_scripts")) {
    if (entry.path().extension() != ".launch") continue;
    ++launch_files;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    for (size_t at = text.find("<arg "); at != std::string::npos; at = text.find("<arg ", at + 1)) {
      // An <include>'s arguments are the included file's, documented there.
      const size_t include = text.rfind("<include", at), closed = text.rfind("</include>", at);
      if (include != std::string::npos && (closed == std::string::npos || closed < include)) {
        continue;
      }
      const std::string tag = text.substr(at, text.find("/>", at) - at);
      ++args;
      EXPECT_NE(tag.find(" doc=\""), std::string::npos) << entry.path().filename() << ": " << tag;
    }
  }
  EXPECT_GE(launch_files, 6u);
  EXPECT_GE(args, 80u);
}

}  // namespace
}  // namespace icgm

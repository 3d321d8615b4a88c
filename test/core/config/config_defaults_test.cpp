// One source of defaults: every value in the shipped config/odometry.yaml, config/icgm.yaml,
// config/map.yaml and config/mono.yaml equals the default of the options struct that reads it, so
// running without a config file, or with a section left out, behaves as the shipped configuration
// does. The defaults are taken from the loaders themselves (OptionReader::Recording records the
// value each key finds in a default-constructed struct), so a new option is covered without adding
// it here.
//
// Deliberate exceptions, each with its reason:
//  - odometry.yaml `icgm:` overrides config/icgm.yaml's `icgm:` for the odometry's
//    frame-to-keyframe matching (wider baselines than consecutive frames: automatic Thr and the
//    wheel motion prior); it cannot equal the defaults, which belong to consecutive-frame ICGM.
//    Its keys must still be options of `icgm:`.
//  - config/thesis is the thesis profile (the thesis's method as written): it differs from the
//    defaults on purpose, each difference commented in the file; it must load as a whole.
//  - camera and simulator files (config/camera, config/sim) describe one sensor or scenario each
//    and are not defaults; their loaders reject unknown keys and they are parsed by the config
//    test.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/option_reader.h"
#include "core/common/status.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/map_export_options.h"
#include "core/mono/mono_options.h"
#include "core/nav/navigation_options.h"
#include "core/odometry/frontend_types.h"
#include "core/place/place_options.h"
#include "core/slam/slam_options.h"

namespace icgm {
namespace {

using Record = OptionReader::DefaultsRecord;

std::string ConfigPath(const std::string& name) {
  return std::string(ICGM_SOURCE_DIR) + "/config/" + name;
}

// Defaults of every key the loaders of odometry.yaml / icgm.yaml / map.yaml read, by full path.
struct Defaults {
  Record odometry, icgm, map, mono, map_export, navigation, place;
};

Defaults RecordDefaults() {
  Defaults d;
  auto odometry = std::make_shared<Record>();
  auto icgm = std::make_shared<Record>();
  auto icgm_tracker = std::make_shared<Record>();
  auto map = std::make_shared<Record>();
  FrontendOptions frontend;
  ReadFrontendOptions(OptionReader::Recording(odometry), OptionReader::Recording(icgm), &frontend);
  TrackerOptions tracker;
  ReadOptions(OptionReader::Recording(icgm_tracker), &tracker);
  SlamOptions slam;
  ReadMapSlamOptions(OptionReader::Recording(map), &slam);
  d.odometry = *odometry;
  d.icgm = *icgm;
  // The tracker reads the same features/matcher/icgm sections: its defaults must agree.
  for (const auto& [key, value] : *icgm_tracker) {
    const auto it = d.icgm.find(key);
    if (it == d.icgm.end()) {
      d.icgm[key] = value;
    } else {
      EXPECT_EQ(it->second.as<std::string>(), value.as<std::string>())
          << key << ": the front end's default differs from the tracker's";
    }
  }
  d.map = *map;
  auto mono = std::make_shared<Record>();
  MonoOptions mono_options;
  ReadMonoOptions(OptionReader::Recording(mono), &mono_options);
  d.mono = *mono;
  auto map_export = std::make_shared<Record>();
  MapExportOptions export_options;
  ReadOptions(OptionReader::Recording(map_export), &export_options);
  d.map_export = *map_export;
  auto navigation = std::make_shared<Record>();
  NavigationOptions nav;
  ReadNavigationOptions(OptionReader::Recording(navigation), &nav);
  d.navigation = *navigation;
  auto place = std::make_shared<Record>();
  PlaceRecognitionOptions place_options;
  ReadPlaceRecognitionFile(OptionReader::Recording(place), &place_options);
  d.place = *place;
  return d;
}

// Equal as the types the readers use: bool, number (int or double, relative 1e-12), string.
bool SameValue(const YAML::Node& a, const YAML::Node& b) {
  const std::string sa = a.as<std::string>(), sb = b.as<std::string>();
  if (sa == sb) return true;
  bool ba = false, bb = false;
  if (YAML::convert<bool>::decode(a, ba) && YAML::convert<bool>::decode(b, bb)) return ba == bb;
  double da = 0.0, db = 0.0;
  if (YAML::convert<double>::decode(a, da) && YAML::convert<double>::decode(b, db)) {
    return std::abs(da - db) <= 1e-12 * std::max(1.0, std::max(std::abs(da), std::abs(db)));
  }
  return false;
}

// Problems of one shipped file against the recorded defaults; `exempt_sections` are compared
// for known keys only.
std::vector<std::string> CompareWithDefaults(const YAML::Node& root, const Record& defaults,
                                             const std::set<std::string>& exempt_sections,
                                             const Record& exempt_defaults = Record()) {
  std::vector<std::string> problems;
  for (const auto& section : root) {
    const std::string name = section.first.as<std::string>();
    const bool exempt = exempt_sections.count(name) > 0;
    for (const auto& kv : section.second) {
      const std::string key = name + "." + kv.first.as<std::string>();
      const Record& known = exempt ? exempt_defaults : defaults;
      const auto it = known.find(key);
      if (it == known.end()) {
        problems.push_back(key + ": no option reads it");
      } else if (!exempt && !SameValue(kv.second, it->second)) {
        problems.push_back(key + ": shipped " + kv.second.as<std::string>() + ", code default " +
                           it->second.as<std::string>());
      }
    }
  }
  return problems;
}

std::string Join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += "\n  " + s;
  return out;
}

class ConfigDefaultsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { defaults_ = std::make_unique<Defaults>(RecordDefaults()); }
  static std::unique_ptr<Defaults> defaults_;
};
std::unique_ptr<Defaults> ConfigDefaultsTest::defaults_;

TEST_F(ConfigDefaultsTest, RecordsEveryLoaderSection) {
  // The recording must see the sections; an empty record would make the comparisons vacuous.
  EXPECT_TRUE(defaults_->odometry.count("frontend.use_icgm"));
  EXPECT_TRUE(defaults_->odometry.count("registration.min_inliers"));
  EXPECT_TRUE(defaults_->odometry.count("wheel_odometry.max_gap_s"));
  EXPECT_TRUE(defaults_->odometry.count("icgm.threshold"));  // the override section
  EXPECT_TRUE(defaults_->icgm.count("features.detector"));
  EXPECT_TRUE(defaults_->icgm.count("matcher.ratio"));
  EXPECT_TRUE(defaults_->icgm.count("icgm.threshold"));
  EXPECT_TRUE(defaults_->icgm.count("tracker.mode"));
  for (const char* section :
       {"dictionary.", "loop_closure.", "map.", "pose_graph.", "keyframe_registration.",
        "map_refinement.", "bundle_adjustment.", "localization.", "map_features."}) {
    const auto it = defaults_->map.lower_bound(section);
    EXPECT_TRUE(it != defaults_->map.end() && it->first.rfind(section, 0) == 0) << section;
  }
}

TEST_F(ConfigDefaultsTest, MonoYamlEqualsCodeDefaults) {
  for (const char* key :
       {"mono.use_icgm", "mono.ba_window_keyframes", "features.max_features", "icgm.threshold",
        "bundle_adjustment.use_depth", "wheel_odometry.max_gap_s"}) {
    EXPECT_TRUE(defaults_->mono.count(key)) << key;
  }
  const auto problems =
      CompareWithDefaults(YAML::LoadFile(ConfigPath("mono.yaml")), defaults_->mono, {});
  EXPECT_TRUE(problems.empty()) << "config/mono.yaml:" << Join(problems);
  // Every key the loader reads is in the file (the file documents all options).
  const YAML::Node file = YAML::LoadFile(ConfigPath("mono.yaml"));
  for (const auto& [key, value] : defaults_->mono) {
    const std::string section = key.substr(0, key.find('.'));
    EXPECT_TRUE(file[section] && file[section][key.substr(key.find('.') + 1)])
        << "config/mono.yaml lacks " << key;
  }
}

TEST_F(ConfigDefaultsTest, OdometryYamlEqualsCodeDefaults) {
  const auto problems = CompareWithDefaults(YAML::LoadFile(ConfigPath("odometry.yaml")),
                                            defaults_->odometry, {"icgm"}, defaults_->icgm);
  EXPECT_TRUE(problems.empty()) << "config/odometry.yaml:" << Join(problems);
}

TEST_F(ConfigDefaultsTest, IcgmYamlEqualsCodeDefaults) {
  const auto problems =
      CompareWithDefaults(YAML::LoadFile(ConfigPath("icgm.yaml")), defaults_->icgm, {});
  EXPECT_TRUE(problems.empty()) << "config/icgm.yaml:" << Join(problems);
}

TEST_F(ConfigDefaultsTest, MapYamlEqualsCodeDefaults) {
  const auto problems =
      CompareWithDefaults(YAML::LoadFile(ConfigPath("map.yaml")), defaults_->map, {});
  EXPECT_TRUE(problems.empty()) << "config/map.yaml:" << Join(problems);
}

TEST_F(ConfigDefaultsTest, PlaceRecognitionYamlEqualsCodeDefaults) {
  for (const char* key :
       {"place_recognition.unverified_weight", "temporal_consistency.consistent_queries",
        "geometric_verification.min_inliers", "geometric_verification.descriptor_fallback",
        "temporal_consistency.continuation", "place_recognition.depth_candidates",
        "place_recognition.depth_min_score", "geometric_verification.rgbd_max_translation_m",
        "geometric_verification.rgbd_max_rotation_deg", "geometric_verification.rgbd_nearest",
        "geometric_verification.rgbd_descriptor_fallback",
        "geometric_verification.rgbd_agreement_min_inliers",
        "temporal_consistency.continuation_min_inliers"}) {
    EXPECT_TRUE(defaults_->place.count(key)) << key;
  }
  const YAML::Node file = YAML::LoadFile(ConfigPath("place_recognition.yaml"));
  const auto problems = CompareWithDefaults(file, defaults_->place, {});
  EXPECT_TRUE(problems.empty()) << "config/place_recognition.yaml:" << Join(problems);
  for (const auto& [key, value] : defaults_->place) {
    const std::string section = key.substr(0, key.find('.'));
    EXPECT_TRUE(file[section] && file[section][key.substr(key.find('.') + 1)])
        << "config/place_recognition.yaml lacks " << key;
  }
}

TEST_F(ConfigDefaultsTest, MapExportYamlEqualsCodeDefaults) {
  for (const char* key : {"map_cloud.voxel_m", "static_points.min_agreement_gap_s",
                          "occupancy_grid.resolution_m", "occupancy_grid.max_height_m"}) {
    EXPECT_TRUE(defaults_->map_export.count(key)) << key;
  }
  const auto problems =
      CompareWithDefaults(YAML::LoadFile(ConfigPath("map_export.yaml")), defaults_->map_export, {});
  EXPECT_TRUE(problems.empty()) << "config/map_export.yaml:" << Join(problems);
}

// The map export loader is strict: unknown keys and sections, and inverted bands, are errors.
TEST(StrictConfigTest, MapExportOptionsRejectUnknownKeysAndBadBands) {
  const auto fails = [](const std::string& yaml, const std::string& expected) {
    MapExportOptions options;
    try {
      ReadOptions(OptionReader::FromString(yaml), &options);
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails("occupancy_grid: {resolution_mm: 5}", "occupancy_grid.resolution_mm");
  fails("occupancy_grids: {resolution_m: 0.05}", "occupancy_grids");
  fails("occupancy_grid: {min_height_m: 1.0, max_height_m: 0.5}", "max_height_m");
  fails("occupancy_grid: {resolution_m: 0}", "occupancy_grid.resolution_m");
  fails("static_points: {max_see_through_share: 1.5}", "static_points.max_see_through_share");
  fails("map_cloud: {voxel_m: -1}", "map_cloud.voxel_m");
  MapExportOptions options;
  ReadOptions(OptionReader::FromString("occupancy_grid: {resolution_m: 0.1}"), &options);
  EXPECT_DOUBLE_EQ(options.grid.resolution_m, 0.1);
}

TEST_F(ConfigDefaultsTest, NavigationYamlEqualsCodeDefaults) {
  for (const char* key : {"navigator.omega", "obstacle_grid.memory_s",
                          "local_planner.max_state_checks", "controller.max_speed_mps"}) {
    EXPECT_TRUE(defaults_->navigation.count(key)) << key;
  }
  const auto problems =
      CompareWithDefaults(YAML::LoadFile(ConfigPath("navigation.yaml")), defaults_->navigation, {});
  EXPECT_TRUE(problems.empty()) << "config/navigation.yaml:" << Join(problems);
  // Every option the loader reads is in the shipped file.
  const YAML::Node shipped = YAML::LoadFile(ConfigPath("navigation.yaml"));
  for (const auto& [key, value] : defaults_->navigation) {
    const auto dot = key.find('.');
    EXPECT_TRUE(shipped[key.substr(0, dot)][key.substr(dot + 1)]) << key << " missing";
  }
}

// The comparison itself must catch a changed value and an unknown key.
TEST_F(ConfigDefaultsTest, ComparisonDetectsDifferences) {
  EXPECT_TRUE(SameValue(YAML::Load("0.1"), YAML::Node(0.1)));
  EXPECT_TRUE(SameValue(YAML::Load("1.0e-8"), YAML::Node(1e-8)));
  EXPECT_TRUE(SameValue(YAML::Load("30"), YAML::Node(30)));
  EXPECT_TRUE(SameValue(YAML::Load("true"), YAML::Node(true)));
  EXPECT_FALSE(SameValue(YAML::Load("0.11"), YAML::Node(0.1)));
  EXPECT_FALSE(SameValue(YAML::Load("false"), YAML::Node(true)));
  EXPECT_FALSE(SameValue(YAML::Load("orb"), YAML::Node(std::string("sift"))));
  Record defaults;
  defaults["a.x"] = YAML::Node(1.5);
  defaults["a.n"] = YAML::Node(3);
  defaults["b.x"] = YAML::Node(1.5);
  EXPECT_TRUE(CompareWithDefaults(YAML::Load("a: {x: 1.5, n: 3}"), defaults, {}).empty());
  EXPECT_EQ(CompareWithDefaults(YAML::Load("a: {x: 1.25, n: 3}"), defaults, {}).size(), 1u);
  EXPECT_EQ(CompareWithDefaults(YAML::Load("a: {x: 1.5, typo: 3}"), defaults, {}).size(), 1u);
  // An exempt section may differ but not hold unknown keys.
  EXPECT_TRUE(CompareWithDefaults(YAML::Load("b: {x: 2}"), defaults, {"b"}, defaults).empty());
  EXPECT_EQ(CompareWithDefaults(YAML::Load("b: {y: 2}"), defaults, {"b"}, defaults).size(), 1u);
}

// The loaders reject a misspelt key in every section of the three files, naming it.
TEST(StrictConfigTest, LoadersRejectUnknownKeysNamingThem) {
  const auto expect_rejected = [](const std::string& what, const std::function<void()>& load,
                                  const std::string& key) {
    try {
      load();
      ADD_FAILURE() << what << ": accepted unknown key " << key;
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << what << ": " << e.what();
    }
  };
  const auto empty = OptionReader::FromString("{}");
  for (const char* section : {"frontend", "registration", "fusion", "wheel_odometry", "icgm",
                              "depth_consistency", "dense_refinement"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "odometry.yaml",
        [&] {
          FrontendOptions o;
          ReadFrontendOptions(OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"),
                              empty, &o);
        },
        key);
  }
  expect_rejected(
      "odometry.yaml top level",
      [&] {
        FrontendOptions o;
        ReadFrontendOptions(OptionReader::FromString("frontnd: {use_icgm: true}"), empty, &o);
      },
      "frontnd");
  for (const char* section : {"features", "matcher", "icgm"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "icgm.yaml (front end)",
        [&] {
          FrontendOptions o;
          ReadFrontendOptions(
              empty, OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"), &o);
        },
        key);
  }
  for (const char* section : {"features", "matcher", "icgm", "tracker"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "icgm.yaml (tracker)",
        [&] {
          TrackerOptions o;
          ReadOptions(OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"), &o);
        },
        key);
  }
  for (const char* section : {"dictionary", "loop_closure", "map", "pose_graph",
                              "keyframe_registration", "map_refinement", "bundle_adjustment"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "map.yaml",
        [&] {
          SlamOptions o;
          ReadMapSlamOptions(OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"),
                             &o);
        },
        key);
  }
  expect_rejected(
      "map.yaml top level",
      [&] {
        SlamOptions o;
        ReadMapSlamOptions(OptionReader::FromString("loop_closur: {max_loops: 3}"), &o);
      },
      "loop_closur");
  for (const char* section :
       {"mono", "features", "matcher", "icgm", "bundle_adjustment", "wheel_odometry"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "mono.yaml",
        [&] {
          MonoOptions o;
          ReadMonoOptions(OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"),
                          &o);
        },
        key);
  }
  expect_rejected(
      "mono.yaml top level",
      [&] {
        MonoOptions o;
        ReadMonoOptions(OptionReader::FromString("mon: {use_icgm: true}"), &o);
      },
      "mon");
  expect_rejected(
      "mono.yaml prior bounds",
      [&] {
        MonoOptions o;
        ReadMonoOptions(
            OptionReader::FromString("mono: {prior_threshold_min: 0.1, prior_threshold_max: 0.05}"),
            &o);
      },
      "mono.prior_threshold_min");
  const std::pair<const char*, const char*> out_of_range[] = {
      {"mono: {cull_outlier_frames: -1}", "mono.cull_outlier_frames"},
      {"mono: {initialization_matches: ransac}", "mono.initialization_matches"},
      {"mono: {new_point_confirm_px: -2.0}", "mono.new_point_confirm_px"},
      {"mono: {new_point_contradiction_px: -1.0}", "mono.new_point_contradiction_px"},
      {"mono: {dynamic_mask_radius_px: -1.0}", "mono.dynamic_mask_radius_px"},
      {"mono: {dynamic_mask_min_votes: 0}", "mono.dynamic_mask_min_votes"},
      {"mono: {pnp_verified_min_keyframes: -1}", "mono.pnp_verified_min_keyframes"},
      {"mono: {pnp_verified_min_span_s: -0.1}", "mono.pnp_verified_min_span_s"},
      {"mono: {pnp_verified_min_points: 3}", "mono.pnp_verified_min_points"},
      {"mono: {scene_depth_band: -1.0}", "mono.scene_depth_band"},
      {"mono: {scene_depth_band: 0.5}", "mono.scene_depth_band"},
      {"mono: {rotation_only_parallax_deg: -1.0}", "mono.rotation_only_parallax_deg"},
      {"mono: {reset_bridge_max_s: -1.0}", "mono.reset_bridge_max_s"},
      {"mono: {relocalize_good_keyframe_points: -1}", "mono.relocalize_good_keyframe_points"},
      {"mono: {new_point_prior_radius_px: 0.0}", "mono.new_point_prior_radius_px"},
      {"mono: {new_point_icgm_baseline_keyframes: -1}", "mono.new_point_icgm_baseline_keyframes"},
      {"mono: {track_icgm_baseline_frames: -1}", "mono.track_icgm_baseline_frames"},
      {"mono: {track_icgm_baseline_max_translation_depth_ratio: -0.01}",
       "mono.track_icgm_baseline_max_translation_depth_ratio"},
      {"mono: {new_point_min_baseline_depth_ratio: -0.01}",
       "mono.new_point_min_baseline_depth_ratio"},
      {"mono: {new_point_min_baseline_depth_ratio: 1.5}",
       "mono.new_point_min_baseline_depth_ratio"},
      {"mono: {keyframe_min_baseline_depth_ratio: -0.01}",
       "mono.keyframe_min_baseline_depth_ratio"},
      {"mono: {keyframe_min_baseline_depth_ratio: 1.5}", "mono.keyframe_min_baseline_depth_ratio"},
      {"mono: {keyframe_force_tracked: -1}", "mono.keyframe_force_tracked"},
      {"mono: {new_point_extra_keyframes: -1}", "mono.new_point_extra_keyframes"},
      {"mono: {new_point_extra_min_baseline_depth_ratio: 1.5}",
       "mono.new_point_extra_min_baseline_depth_ratio"},
      {"mono: {relocalize_while_initializing: 2}", "mono.relocalize_while_initializing"},
      {"bundle_adjustment: {max_solver_time_s: -1.0}", "bundle_adjustment.max_solver_time_s"}};
  for (const auto& [yaml, key] : out_of_range) {
    expect_rejected(
        "mono.yaml range",
        [&] {
          MonoOptions o;
          ReadMonoOptions(OptionReader::FromString(yaml), &o);
        },
        key);
  }
  EXPECT_NO_THROW(LoadMonoOptions(ConfigPath("mono.yaml")));
  for (const char* section : {"navigator", "obstacle_grid", "local_planner", "controller"}) {
    const std::string key = std::string(section) + ".no_such_key";
    expect_rejected(
        "navigation.yaml",
        [&] {
          NavigationOptions o;
          ReadNavigationOptions(
              OptionReader::FromString(std::string(section) + ": {no_such_key: 1}"), &o);
        },
        key);
  }
  expect_rejected(
      "navigation.yaml top level",
      [&] {
        NavigationOptions o;
        ReadNavigationOptions(OptionReader::FromString("navigatr: {omega: 3}"), &o);
      },
      "navigatr");
  expect_rejected(
      "navigation.yaml range",
      [&] {
        NavigationOptions o;
        ReadNavigationOptions(OptionReader::FromString("navigator: {omega: 0}"), &o);
      },
      "navigator.omega");
  for (const char* key : {"goal_line_tolerance_m", "goal_extension_m", "detour_join_m",
                          "rejoin_dubins_radius_m", "rejoin_max_s"}) {
    expect_rejected(
        "navigation.yaml range",
        [&] {
          NavigationOptions o;
          ReadNavigationOptions(
              OptionReader::FromString("navigator: {" + std::string(key) + ": -0.1}"), &o);
        },
        std::string("navigator.") + key);
  }
  expect_rejected(
      "navigation.yaml range",
      [&] {
        NavigationOptions o;
        ReadNavigationOptions(OptionReader::FromString("controller: {away_turn_rad: -0.1}"), &o);
      },
      "controller.away_turn_rad");
  // The shipped files themselves load.
  EXPECT_NO_THROW(LoadSlamOptions(std::string(ICGM_SOURCE_DIR) + "/config"));
  TrackerOptions tracker;
  EXPECT_NO_THROW(ReadOptions(OptionReader::FromFile(ConfigPath("icgm.yaml")), &tracker));
}

// The thesis profile loads as a configuration folder and turns our extensions off.
TEST(ThesisProfileTest, RunsTheThesisMethodAsWritten) {
  const SlamOptions thesis = LoadSlamOptions(ConfigPath("thesis"));
  const SlamOptions ours = LoadSlamOptions(ConfigPath(""));
  EXPECT_EQ(thesis.frontend.icgm.seed_pairs, 1);  // Algorithm 1
  EXPECT_GT(ours.frontend.icgm.seed_pairs, 1);
  EXPECT_FALSE(thesis.frontend.icgm.motion_prior);
  EXPECT_FALSE(thesis.frontend.icgm.auto_threshold);
  EXPECT_EQ(thesis.frontend.fusion.max_vision_wheel_disagreement_m, 0.0);
  EXPECT_GE(thesis.map.loop_closure.gate_sigma, 1e5);
  EXPECT_EQ(thesis.map.loop_closure.correction, LoopCorrection::kSemiConsensus);
  // 6.1.3.1: the map's features from double-directional ICGM over consecutive frames, S = 3.
  EXPECT_EQ(thesis.map_features.source, MapFeatureSource::kTracker);
  EXPECT_EQ(ours.map_features.source, MapFeatureSource::kReferenceKeyframe);
  EXPECT_EQ(thesis.map_features.tracker.mode, TrackerMode::kDouble);
  EXPECT_EQ(thesis.map_features.tracker.window_size, 3);
  EXPECT_EQ(thesis.map_features.tracker.icgm.seed_pairs, 1);
  TrackerOptions tracker;
  ReadOptions(OptionReader::FromFile(ConfigPath("thesis/icgm.yaml")), &tracker);
  EXPECT_EQ(tracker.mode, TrackerMode::kDouble);
  EXPECT_EQ(tracker.window_size, 3);  // 6.1.3.1: S = 3
  // 3.2, 4.1: SURF everywhere (front end, map features, place recognition), so a float
  // dictionary; the defaults keep ORB and a binary one.
  EXPECT_EQ(thesis.frontend.features.detector, Detector::kSurf);
  EXPECT_EQ(tracker.features.detector, Detector::kSurf);
  EXPECT_EQ(thesis.map.dictionary.descriptor_type, DescriptorType::kFloat);
  EXPECT_EQ(ours.frontend.features.detector, Detector::kOrb);
  EXPECT_EQ(ours.map.dictionary.descriptor_type, DescriptorType::kBinary);
  EXPECT_NO_THROW(CheckFeaturesFitDictionary(thesis));
  EXPECT_NO_THROW(CheckFeaturesFitDictionary(ours));
  // 4.2: ICGM-verified features only, the best-scored image, none of our checks.
  PlaceRecognitionOptions place_thesis, place_ours;
  ReadPlaceRecognitionFile(OptionReader::FromFile(ConfigPath("thesis/place_recognition.yaml")),
                           &place_thesis);
  EXPECT_EQ(place_thesis.unverified_weight, 0.0);
  EXPECT_GT(place_ours.unverified_weight, 0.0);
  EXPECT_FALSE(place_thesis.weight_by_verified_share);
  EXPECT_EQ(place_thesis.min_query_words, 0);
  EXPECT_EQ(place_thesis.candidates, 1);
  EXPECT_EQ(place_thesis.temporal.consistent_queries, 0);
  EXPECT_FALSE(place_thesis.temporal.continuation);
  EXPECT_TRUE(place_ours.temporal.continuation);
  EXPECT_FALSE(place_thesis.geometry.enabled);
  EXPECT_TRUE(place_ours.geometry.enabled);
  // Depth candidates, the nearest view and the RGB-D descriptor fallback are ours: off there.
  EXPECT_EQ(place_thesis.depth_candidates, 0);
  EXPECT_FALSE(place_thesis.geometry.rgbd_nearest);
  EXPECT_FALSE(place_thesis.geometry.rgbd_descriptor_fallback);
  EXPECT_GT(place_ours.depth_candidates, 0);
  EXPECT_TRUE(place_ours.geometry.rgbd_descriptor_fallback);
  // Fewer inliers on the agreement of two checks (ours): off there.
  EXPECT_EQ(place_thesis.temporal.continuation_min_inliers, 0);
  EXPECT_EQ(place_thesis.geometry.rgbd_agreement_min_inliers, 0);
}

// A dictionary that cannot hold the front end's descriptors is refused before any frame, with
// both keys named (a binary dictionary given SURF would otherwise fail on the first keyframe).
TEST(ThesisProfileTest, DictionaryMustHoldTheFrontEndsDescriptors) {
  SlamOptions options = LoadSlamOptions(ConfigPath("thesis"));
  options.map.dictionary.descriptor_type = DescriptorType::kBinary;
  try {
    CheckFeaturesFitDictionary(options);
    ADD_FAILURE() << "a binary dictionary with SURF was accepted";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dictionary.descriptor_type"), std::string::npos) << what;
    EXPECT_NE(what.find("features.detector 'surf'"), std::string::npos) << what;
    EXPECT_NE(what.find("use float"), std::string::npos) << what;
  }
  options.build_map = false;  // the front end alone keeps no dictionary
  EXPECT_NO_THROW(CheckFeaturesFitDictionary(options));
  SlamOptions ours = LoadSlamOptions(ConfigPath(""));
  ours.map.dictionary.descriptor_type = DescriptorType::kFloat;
  EXPECT_THROW(CheckFeaturesFitDictionary(ours), LoadError);
}

// The local-map keys reach the front end's options and are range-checked.
TEST(LocalMapConfigTest, KeysAreReadAndChecked) {
  const auto empty = OptionReader::FromString("{}");
  FrontendOptions o;
  ReadFrontendOptions(OptionReader::FromString("frontend: {local_map_keyframes: 6, "
                                               "local_map_search_px: 4.0, local_map_fuse: true, "
                                               "local_map_covariance_scale: 10.0, "
                                               "local_map_toward_prediction: true, "
                                               "local_map_toward_prediction_slack_m: 0.002}"),
                      empty, &o);
  EXPECT_EQ(o.local_map.keyframes, 6);
  EXPECT_EQ(o.local_map.search_px, 4.0);
  EXPECT_TRUE(o.local_map.fuse);
  EXPECT_EQ(o.local_map.covariance_scale, 10.0);
  EXPECT_TRUE(o.local_map.toward_prediction);
  EXPECT_EQ(o.local_map.toward_prediction_slack_m, 0.002);
  EXPECT_FALSE(FrontendOptions().local_map.toward_prediction);  // off by default
  EXPECT_EQ(FrontendOptions().local_map.keyframes, 0);  // off by default
  FrontendOptions bad;
  EXPECT_THROW(ReadFrontendOptions(OptionReader::FromString("frontend: {local_map_keyframes: -1}"),
                                   empty, &bad),
               LoadError);
  EXPECT_THROW(ReadFrontendOptions(OptionReader::FromString(
                                       "frontend: {local_map_toward_prediction_slack_m: -0.01}"),
                                   empty, &bad),
               LoadError);
}

// The map hypothesis keys reach the front end's options and are range-checked.
TEST(MapHypothesisConfigTest, KeysAreReadAndChecked) {
  const auto empty = OptionReader::FromString("{}");
  FrontendOptions o;
  ReadFrontendOptions(
      OptionReader::FromString("frontend: {map_hypothesis_keyframes: 6, map_hypothesis_ratio: 0.9, "
                               "map_hypothesis_window_px: 40.0, "
                               "map_hypothesis_evidence_weight: 0.5}"),
      empty, &o);
  EXPECT_EQ(o.map_hypothesis.keyframes, 6);
  EXPECT_EQ(o.map_hypothesis.ratio, 0.9);
  EXPECT_EQ(o.map_hypothesis.window_px, 40.0);
  EXPECT_EQ(o.map_hypothesis.evidence_weight, 0.5);
  EXPECT_EQ(FrontendOptions().map_hypothesis.keyframes, 0);  // off by default
  FrontendOptions bad;
  EXPECT_THROW(ReadFrontendOptions(
                   OptionReader::FromString("frontend: {map_hypothesis_ratio: 1.5}"), empty, &bad),
               LoadError);
}

// The keyframe bundle adjustment keys reach the front end's options and are range-checked.
TEST(KeyframeBaConfigTest, KeysAreReadAndChecked) {
  const auto empty = OptionReader::FromString("{}");
  FrontendOptions o;
  ReadFrontendOptions(OptionReader::FromString("frontend: {keyframe_ba_keyframes: 5, "
                                               "keyframe_ba_min_spacing_m: 0.02, "
                                               "keyframe_ba_depth_sigma_per_m2: 0.0019, "
                                               "keyframe_ba_link_covariance_scale: 10.0}"),
                      empty, &o);
  EXPECT_EQ(o.keyframe_ba.keyframes, 5);
  EXPECT_EQ(o.keyframe_ba.min_spacing_m, 0.02);
  EXPECT_EQ(o.keyframe_ba.depth_sigma_per_m2, 0.0019);
  EXPECT_EQ(o.keyframe_ba.link_covariance_scale, 10.0);
  EXPECT_EQ(FrontendOptions().keyframe_ba.keyframes, 0);  // off by default
  FrontendOptions bad;
  EXPECT_THROW(
      ReadFrontendOptions(OptionReader::FromString("frontend: {keyframe_ba_fixed_keyframes: 0}"),
                          empty, &bad),
      LoadError);
}

}  // namespace
}  // namespace icgm

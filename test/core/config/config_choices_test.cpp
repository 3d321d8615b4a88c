// Every option that takes one of a set of names (an enum class read by OptionReader::ReadEnum)
// is checked through the loader of the shipped file that holds it: each allowed spelling loads
// and reads back as itself, the shipped value is one of them, and a misspelt value is refused
// with an error naming the key and listing the allowed spellings. The lists are written out here,
// so renaming a spelling the shipped configs and users' files rely on fails this test.
#include <algorithm>
#include <cctype>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/common/enum_names.h"
#include "core/common/option_reader.h"
#include "core/common/status.h"
#include "core/icgm/robust_feature_tracker.h"
#include "core/map/pose_graph_optimizer.h"
#include "core/sim/sim_options.h"
#include "core/slam/slam_options.h"

namespace icgm {
namespace {

struct ChoiceCase {
  std::string file;     // under config/
  std::string section;  // top-level section of the file
  std::string key;
  std::vector<std::string> allowed;
  // Loads the whole file (its root) with the loader the programs use; returns the option's
  // value spelt back with NameOf.
  std::function<std::string(const OptionReader& root)> load;
};

std::string TrackerField(const OptionReader& root,
                         const std::function<std::string(const TrackerOptions&)>& field) {
  TrackerOptions options;
  ReadOptions(root, &options);
  return field(options);
}

std::string MapField(const OptionReader& root,
                     const std::function<std::string(const SlamOptions&)>& field) {
  SlamOptions options;
  ReadMapSlamOptions(root, &options);
  return field(options);
}

void PrintTo(const ChoiceCase& c, std::ostream* os) { *os << c.section << "." << c.key; }

std::vector<ChoiceCase> Cases() {
  return {
      {"icgm.yaml",
       "features",
       "detector",
       {"orb", "sift", "akaze", "gftt_orb", "surf"},
       [](const OptionReader& root) {
         return TrackerField(root, [](const auto& o) { return NameOf(o.features.detector); });
       }},
      {"icgm.yaml",
       "matcher",
       "binary_index",
       {"bf", "lsh"},
       [](const OptionReader& root) {
         return TrackerField(root, [](const auto& o) { return NameOf(o.matcher.binary_index); });
       }},
      {"icgm.yaml",
       "tracker",
       "mode",
       {"single", "double", "pirf"},
       [](const OptionReader& root) {
         return TrackerField(root, [](const auto& o) { return NameOf(o.mode); });
       }},
      {"map.yaml",
       "dictionary",
       "descriptor_type",
       {"binary", "float"},
       [](const OptionReader& root) {
         return MapField(root,
                         [](const auto& o) { return NameOf(o.map.dictionary.descriptor_type); });
       }},
      {"map.yaml",
       "loop_closure",
       "correction",
       {"semi_consensus", "pose_graph"},
       [](const OptionReader& root) {
         return MapField(root, [](const auto& o) { return NameOf(o.map.loop_closure.correction); });
       }},
      {"map.yaml",
       "map",
       "visual_information",
       {"fixed", "registration"},
       [](const OptionReader& root) {
         return MapField(root, [](const auto& o) { return NameOf(o.map.map.visual_information); });
       }},
      {"map.yaml",
       "pose_graph",
       "loss",
       {"huber", "cauchy", "none"},
       [](const OptionReader& root) {
         return MapField(root, [](const auto& o) { return NameOf(o.map.pose_graph.loss); });
       }},
      {"map.yaml",
       "localization",
       "keyframes",
       {"none", "session"},
       [](const OptionReader& root) {
         return MapField(root, [](const auto& o) { return NameOf(o.localization.keyframes); });
       }},
      {"sim/handheld_crowd.yaml",
       "sim",
       "camera_motion",
       {"wheeled", "handheld"},
       [](const OptionReader& root) {
         // The scenario's other settings belong to its own camera motion (a hand-held room is
         // too small for the robot's route): the simulator's reader gets this key alone.
         YAML::Node sim;
         sim["camera_motion"] = root.node()["sim"]["camera_motion"];
         sim::SimOptions options;
         ReadOptions(OptionReader(sim, "sim"), &options);
         return std::string(NameOf(options.camera_motion));
       }},
  };
}

std::string ConfigPath(const std::string& name) {
  return std::string(ICGM_SOURCE_DIR) + "/config/" + name;
}

// The shipped file with `section.key` set to `value` (a fresh copy: YAML nodes share storage).
OptionReader WithValue(const ChoiceCase& c, const std::string& value) {
  YAML::Node root = YAML::Clone(YAML::LoadFile(ConfigPath(c.file)));
  root[c.section][c.key] = value;
  return OptionReader(root, "");
}

std::string Braced(const std::vector<std::string>& names) {
  std::string out = "{";
  for (size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out + "}";
}

std::string CaseName(const ::testing::TestParamInfo<ChoiceCase>& info) {
  return info.param.section + "_" + info.param.key;
}

class ConfigChoiceTest : public ::testing::TestWithParam<ChoiceCase> {};

TEST_P(ConfigChoiceTest, ShippedValueIsAnAllowedSpelling) {
  const ChoiceCase& c = GetParam();
  const YAML::Node shipped = YAML::LoadFile(ConfigPath(c.file))[c.section][c.key];
  ASSERT_TRUE(shipped) << c.file << " has no " << c.section << "." << c.key;
  const std::string value = shipped.as<std::string>();
  EXPECT_EQ(c.load(OptionReader::FromFile(ConfigPath(c.file))), value);
  EXPECT_NE(std::find(c.allowed.begin(), c.allowed.end(), value), c.allowed.end()) << value;
}

TEST_P(ConfigChoiceTest, EveryAllowedSpellingLoadsAsItself) {
  const ChoiceCase& c = GetParam();
  for (const std::string& value : c.allowed) {
    if (value == "pose_graph" && !PoseGraphOptimizer::Available()) continue;  // needs Ceres
    try {
      EXPECT_EQ(c.load(WithValue(c, value)), value);
    } catch (const LoadError& e) {
      ADD_FAILURE() << c.section << "." << c.key << ": " << value << " refused: " << e.what();
    }
  }
}

TEST_P(ConfigChoiceTest, MisspeltValueIsRefusedWithTheAllowedSpellings) {
  const ChoiceCase& c = GetParam();
  // A near miss of the first spelling (upper case) and an unrelated word.
  std::string upper = c.allowed.front();
  for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  for (const std::string& wrong : {upper, std::string("bogus")}) {
    try {
      c.load(WithValue(c, wrong));
      ADD_FAILURE() << c.section << "." << c.key << ": '" << wrong << "' was accepted";
    } catch (const LoadError& e) {
      EXPECT_EQ(std::string(e.what()),
                c.section + "." + c.key + ": '" + wrong + "' is not one of " + Braced(c.allowed));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, ConfigChoiceTest, ::testing::ValuesIn(Cases()), CaseName);

}  // namespace
}  // namespace icgm

#include "core/map/map_options.h"

#include <gtest/gtest.h>

#include <string>

namespace icgm {
namespace {

TEST(MapOptionsTest, ShippedConfigLoadsWithoutUnknownKeys) {
  const OptionReader root =
      OptionReader::FromFile(std::string(ICGM_SOURCE_DIR) + "/config/map.yaml");
  MapBuilderOptions options;
  options.dictionary.new_word_distance_bits = -1;
  std::vector<std::string> unused;
  ReadOptions(root, &options, &unused);
  EXPECT_TRUE(unused.empty()) << unused.front();
  EXPECT_EQ(options.dictionary.new_word_distance_bits, 40);
  EXPECT_EQ(options.loop_closure.candidates_per_loop, 3);
  EXPECT_GT(options.loop_closure.alpha_mapping, 0.0);
  EXPECT_LT(options.loop_closure.alpha_mapping, 1.0);
  EXPECT_EQ(options.loop_closure.alpha_localization, 1.0);
  EXPECT_TRUE(options.map.wheel_links);
}

TEST(MapOptionsTest, TyposAreReported) {
  MapBuilderOptions options;
  std::vector<std::string> unused;
  ReadOptions(OptionReader::FromString("loop_closure: {min_inlier: 30}"), &options, &unused);
  ASSERT_EQ(unused.size(), 1u);
  EXPECT_EQ(unused[0], "loop_closure.min_inlier");
}

TEST(MapOptionsTest, OutOfRangeValuesNameTheKey) {
  MapBuilderOptions options;
  try {
    ReadOptions(OptionReader::FromString("loop_closure: {alpha_mapping: 1.5}"), &options);
    FAIL() << "accepted alpha 1.5";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("loop_closure.alpha_mapping"), std::string::npos);
  }
  EXPECT_THROW(
      ReadOptions(OptionReader::FromString("dictionary: {descriptor_type: surf}"), &options),
      LoadError);
  EXPECT_THROW(ReadOptions(OptionReader::FromString("loop_closure: {alpha_mapping: 0}"), &options),
               LoadError);
  EXPECT_THROW(
      ReadOptions(OptionReader::FromString("dictionary: {coarse_cells: 4, probe_cells: 8}"),
                  &options),
      LoadError);
}

}  // namespace
}  // namespace icgm

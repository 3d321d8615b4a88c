#include "core/common/option_reader.h"

#include <gtest/gtest.h>

namespace icgm {

enum class TestDetector { kOrb, kSift };
template <>
struct EnumNames<TestDetector> {
  static constexpr EnumName<TestDetector> kNames[] = {{TestDetector::kOrb, "orb"},
                                                      {TestDetector::kSift, "sift"}};
};

namespace {

TEST(OptionReaderTest, ReadsTypedValuesAndKeepsDefaults) {
  const auto r = OptionReader::FromString("a: 0.5\nsec: {n: 3, flag: true, s: orb}\n");
  double a = 0.1;
  double missing = 7.0;
  r.Read("a", &a, 0.0, 1.0);
  r.Read("missing", &missing, 0.0, 10.0);
  EXPECT_DOUBLE_EQ(a, 0.5);
  EXPECT_DOUBLE_EQ(missing, 7.0);
  const auto s = r.Section("sec");
  int n = 0;
  bool flag = false;
  TestDetector detector = TestDetector::kSift;
  s.Read("n", &n, 0, 10);
  s.Read("flag", &flag);
  s.ReadEnum("s", &detector);
  EXPECT_EQ(n, 3);
  EXPECT_TRUE(flag);
  EXPECT_EQ(detector, TestDetector::kOrb);
  EXPECT_TRUE(r.UnusedKeys().empty());
}

TEST(OptionReaderTest, OutOfRangeNamesTheKey) {
  const auto r = OptionReader::FromString("icgm: {threshold: 3.5}\n");
  double thr = 0.1;
  try {
    r.Section("icgm").Read("threshold", &thr, 0.0, 1.0);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("icgm.threshold"), std::string::npos);
  }
  EXPECT_DOUBLE_EQ(thr, 0.1);
}

TEST(OptionReaderTest, WrongTypeAndBadChoiceThrow) {
  const auto r = OptionReader::FromString("n: abc\ns: surf\n");
  int n = 0;
  TestDetector s = TestDetector::kSift;
  EXPECT_THROW(r.Read("n", &n, 0, 10), LoadError);
  try {
    r.ReadEnum("s", &s);
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    EXPECT_STREQ(e.what(), "s: 'surf' is not one of {orb, sift}");
  }
  EXPECT_EQ(s, TestDetector::kSift) << "a refused value leaves the default";
}

TEST(OptionReaderTest, EnumNamesConvertBothWays) {
  EXPECT_STREQ(NameOf(TestDetector::kSift), "sift");
  EXPECT_EQ(ParseEnum<TestDetector>("orb"), TestDetector::kOrb);
  EXPECT_FALSE(ParseEnum<TestDetector>("ORB")) << "spellings are exact";
  EXPECT_FALSE(ParseEnum<TestDetector>(""));
  EXPECT_EQ(EnumChoices<TestDetector>(), (std::vector<std::string>{"orb", "sift"}));
  EXPECT_EQ(NotOneOf<TestDetector>("brief"), "'brief' is not one of {orb, sift}");
}

TEST(OptionReaderTest, ReportsUnusedKeysAndBadFiles) {
  const auto r = OptionReader::FromString("known: 1\ntypo_key: 2\n");
  int k = 0;
  r.Read("known", &k, 0, 5);
  ASSERT_EQ(r.UnusedKeys().size(), 1u);
  EXPECT_EQ(r.UnusedKeys()[0], "typo_key");
  EXPECT_THROW(OptionReader::FromFile("/nonexistent/x.yaml"), LoadError);
  EXPECT_THROW(OptionReader::FromString("a: [1, 2"), LoadError);
}

TEST(OptionReaderTest, RejectUnknownKeysNamesEachKey) {
  const auto r = OptionReader::FromString("sec: {known: 1, typo_a: 2, typo_b: 3}\n");
  const auto sec = r.Section("sec");
  int k = 0;
  sec.Read("known", &k, 0, 5);
  EXPECT_NO_THROW(r.RejectUnknownKeys());
  try {
    sec.RejectUnknownKeys();
    FAIL() << "expected LoadError";
  } catch (const LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sec.typo_a"), std::string::npos) << what;
    EXPECT_NE(what.find("sec.typo_b"), std::string::npos) << what;
    EXPECT_EQ(what.find("sec.known"), std::string::npos) << what;
  }
}

TEST(OptionReaderTest, RecordingKeepsDefaultsByFullPath) {
  auto record = std::make_shared<OptionReader::DefaultsRecord>();
  const auto root = OptionReader::Recording(record);
  double thr = 0.08;
  int n = 5;
  bool flag = true;
  TestDetector detector = TestDetector::kSift;
  root.Section("icgm").Read("threshold", &thr, 0.0, 1.0);
  root.Section("icgm").Read("seeds", &n, 0, 10);
  root.Read("flag", &flag);
  root.Section("features").ReadEnum("detector", &detector);
  ASSERT_EQ(record->size(), 4u);
  EXPECT_DOUBLE_EQ(record->at("icgm.threshold").as<double>(), 0.08);
  EXPECT_EQ(record->at("icgm.seeds").as<int>(), 5);
  EXPECT_TRUE(record->at("flag").as<bool>());
  EXPECT_EQ(record->at("features.detector").as<std::string>(), "sift") << "recorded as spelt";
  EXPECT_DOUBLE_EQ(thr, 0.08);  // nothing read: the values stay
}

}  // namespace
}  // namespace icgm

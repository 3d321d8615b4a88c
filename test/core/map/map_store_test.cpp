#include "core/map/map_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/map/se3_geodesic.h"
#include "test_poses.h"

namespace icgm {
namespace {

namespace fs = std::filesystem;

class MapStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("icgm_map_store_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// A map with two sessions, several loops, binary and float descriptors, loop links.
HybridMap MakeMap(unsigned seed, int keyframes_per_session) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 640.f);
  HybridMap map;
  int id = -1;
  for (int s = 0; s < 2; ++s) {
    map.StartSession(s == 0 ? "daylight" : "night \"lamp\"");
    for (int k = 0; k < keyframes_per_session; ++k) {
      if (k == keyframes_per_session / 2) map.StartLoop();
      Keyframe kf;
      kf.stamp = Time::FromNanoseconds(1305031102175304000LL + 33333333LL * k + s);
      const int n = 5 + k % 4;
      kf.descriptors = cv::Mat(n, s == 0 ? 32 : 8, s == 0 ? CV_8U : CV_32F);
      cv::randu(kf.descriptors, 0, 255);
      for (int i = 0; i < n; ++i) {
        kf.keypoints.emplace_back(u(rng), u(rng), 7.5f, u(rng) / 2, 0.001f * i, i % 3, i);
        kf.points_m.emplace_back(u(rng) / 100, u(rng) / 100, 1.0 + u(rng) / 300);
      }
      kf.points_m.back().z() = std::numeric_limits<double>::quiet_NaN();
      if (s == 0) {
        for (int i = 0; i < n; ++i) kf.word_ids.push_back(7 * k + i);
      }
      kf.relative_pose = GeodesicExp(test::RandomTwist(&rng, 0.3, 0.1));
      kf.relative_source =
          k % 3 == 0 ? RelativePoseSource::kWheelOdometry : RelativePoseSource::kVisual;
      Mat6 info = Mat6::Identity() * (1.0 + k);
      info(0, 1) = info(1, 0) = 0.25;
      EXPECT_TRUE(map.AddKeyframe(kf, info, &id));
    }
    Link loop;
    loop.from_id = id - keyframes_per_session + 1;
    loop.to_id = id;
    loop.type = LinkType::kLoopClosure;
    loop.relative_pose = GeodesicExp(test::RandomTwist(&rng, 0.1, 0.05));
    loop.inliers = 42;
    EXPECT_TRUE(map.AddLink(loop));
    Link wheel;
    wheel.from_id = id - 1;
    wheel.to_id = id;
    wheel.type = LinkType::kWheelOdometry;
    wheel.relative_pose = GeodesicExp(test::RandomTwist(&rng, 0.2, 0.02));
    wheel.information = Mat6::Identity() * 400.0;
    EXPECT_TRUE(map.AddLink(wheel));
    EXPECT_TRUE(map.ApplySemiConsensus(id, map.keyframe(id).global_pose * loop.relative_pose, 0.5));
  }
  return map;
}

bool SameBits(const Pose3& a, const Pose3& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), 16 * sizeof(double)) == 0;
}

void ExpectIdentical(const HybridMap& a, const HybridMap& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.sessions().size(), b.sessions().size());
  ASSERT_EQ(a.loops().size(), b.loops().size());
  ASSERT_EQ(a.links().size(), b.links().size());
  for (size_t i = 0; i < a.sessions().size(); ++i) {
    EXPECT_EQ(a.sessions()[i].name, b.sessions()[i].name);
    EXPECT_EQ(a.sessions()[i].last_corrected_id, b.sessions()[i].last_corrected_id);
    EXPECT_TRUE(SameBits(a.sessions()[i].origin, b.sessions()[i].origin));
  }
  for (size_t i = 0; i < a.loops().size(); ++i) {
    EXPECT_EQ(a.loops()[i].session_id, b.loops()[i].session_id);
    EXPECT_EQ(a.loops()[i].keyframe_ids, b.loops()[i].keyframe_ids);
  }
  for (int i = 0; i < a.size(); ++i) {
    const Keyframe& x = a.keyframe(i);
    const Keyframe& y = b.keyframe(i);
    EXPECT_EQ(x.session_id, y.session_id);
    EXPECT_EQ(x.loop_id, y.loop_id);
    EXPECT_EQ(x.previous_id, y.previous_id);
    EXPECT_EQ(x.stamp, y.stamp);
    EXPECT_EQ(x.relative_source, y.relative_source);
    EXPECT_EQ(x.word_ids, y.word_ids);
    EXPECT_TRUE(SameBits(x.relative_pose, y.relative_pose));
    EXPECT_TRUE(SameBits(x.global_pose, y.global_pose));
    ASSERT_EQ(x.descriptors.type(), y.descriptors.type());
    ASSERT_EQ(x.descriptors.size(), y.descriptors.size());
    EXPECT_EQ(cv::norm(x.descriptors, y.descriptors, cv::NORM_INF), 0.0);
    ASSERT_EQ(x.keypoints.size(), y.keypoints.size());
    for (size_t k = 0; k < x.keypoints.size(); ++k) {
      EXPECT_EQ(x.keypoints[k].pt, y.keypoints[k].pt);
      EXPECT_EQ(x.keypoints[k].size, y.keypoints[k].size);
      EXPECT_EQ(x.keypoints[k].angle, y.keypoints[k].angle);
      EXPECT_EQ(x.keypoints[k].response, y.keypoints[k].response);
      EXPECT_EQ(x.keypoints[k].octave, y.keypoints[k].octave);
      EXPECT_EQ(x.keypoints[k].class_id, y.keypoints[k].class_id);
      EXPECT_EQ(std::memcmp(x.points_m[k].data(), y.points_m[k].data(), 3 * sizeof(double)), 0);
    }
  }
  for (size_t i = 0; i < a.links().size(); ++i) {
    EXPECT_EQ(a.links()[i].from_id, b.links()[i].from_id);
    EXPECT_EQ(a.links()[i].to_id, b.links()[i].to_id);
    EXPECT_EQ(a.links()[i].type, b.links()[i].type);
    EXPECT_EQ(a.links()[i].inliers, b.links()[i].inliers);
    EXPECT_TRUE(SameBits(a.links()[i].relative_pose, b.links()[i].relative_pose));
    EXPECT_EQ(a.links()[i].information, b.links()[i].information);
  }
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST_F(MapStoreTest, SaveLoadRoundTripIsIdentical) {
  const HybridMap map = MakeMap(1, 12);
  ASSERT_TRUE(SaveMap(map, Path("a.db")));
  const HybridMap loaded = LoadMap(Path("a.db"));
  ExpectIdentical(map, loaded);
  ASSERT_TRUE(SaveMap(loaded, Path("b.db")));
  ExpectIdentical(map, LoadMap(Path("b.db")));
  // No temporary file is left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 2);
}

TEST_F(MapStoreTest, SaveReplacesAnExistingMapAndFailedSaveReportsWhy) {
  ASSERT_TRUE(SaveMap(MakeMap(1, 6), Path("m.db")));
  const HybridMap second = MakeMap(2, 9);
  ASSERT_TRUE(SaveMap(second, Path("m.db")));
  ExpectIdentical(second, LoadMap(Path("m.db")));
  const Status s = SaveMap(second, Path("missing_dir/m.db"));
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("missing_dir"), std::string::npos);
}

TEST_F(MapStoreTest, ReadOnlyMapIsNeverReplaced) {
  const HybridMap first = MakeMap(1, 6);
  ASSERT_TRUE(SaveMap(first, Path("ro.db")));
  const std::string before = ReadBytes(Path("ro.db"));
  fs::permissions(Path("ro.db"), fs::perms::owner_read | fs::perms::group_read |
                                     fs::perms::others_read);
  // Refused up front (tools check before processing) and by the save itself, even when the
  // process could write the file anyway (root).
  const Status check = CheckMapWritable(Path("ro.db"));
  EXPECT_FALSE(check.ok());
  EXPECT_NE(check.reason().find("read-only"), std::string::npos) << check.reason();
  EXPECT_NE(check.reason().find("ro.db"), std::string::npos) << check.reason();
  const Status saved = SaveMap(MakeMap(2, 9), Path("ro.db"));
  EXPECT_FALSE(saved.ok());
  EXPECT_EQ(ReadBytes(Path("ro.db")), before);
  ExpectIdentical(first, LoadMap(Path("ro.db")));
  // A writable file and a new file in a writable folder pass; a missing folder does not.
  fs::permissions(Path("ro.db"), fs::perms::owner_write, fs::perm_options::add);
  EXPECT_TRUE(CheckMapWritable(Path("ro.db")).ok());
  EXPECT_TRUE(CheckMapWritable(Path("new.db")).ok());
  EXPECT_FALSE(CheckMapWritable(Path("missing_dir/new.db")).ok());
  EXPECT_FALSE(CheckMapWritable(dir_.string()).ok());  // a folder
}

TEST_F(MapStoreTest, SaveRemovesTemporariesOfKilledSaves) {
  // A pid that cannot be running: above the kernel's pid_max (at most 2^22).
  const std::string stale = Path("m.db.tmp.99999999");
  const std::string own_live = Path("m.db.tmp.1");  // pid 1 exists: a save in progress
  const std::string other = Path("other.db.tmp.99999999");
  for (const std::string& p : {stale, own_live, other}) std::ofstream(p) << "partial";
  const HybridMap map = MakeMap(1, 4);
  ASSERT_TRUE(SaveMap(map, Path("m.db")));
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(own_live));
  EXPECT_TRUE(fs::exists(other));  // another map's temporaries are not this save's business
  ExpectIdentical(map, LoadMap(Path("m.db")));
}

TEST_F(MapStoreTest, TruncatedMapIsRefusedAndLeftUntouched) {
  ASSERT_TRUE(SaveMap(MakeMap(3, 40), Path("m.db")));
  const std::string full = ReadBytes(Path("m.db"));
  ASSERT_GT(full.size(), 8192u);
  for (size_t keep : {full.size() - 1000, full.size() / 2, size_t{4096}, size_t{50}}) {
    {
      std::ofstream out(Path("t.db"), std::ios::binary | std::ios::trunc);
      out.write(full.data(), static_cast<std::streamsize>(keep));
    }
    const std::string before = ReadBytes(Path("t.db"));
    try {
      LoadMap(Path("t.db"));
      ADD_FAILURE() << "accepted a map truncated to " << keep << " bytes";
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find("t.db"), std::string::npos) << e.what();
    }
    EXPECT_EQ(ReadBytes(Path("t.db")), before);
  }
}

TEST_F(MapStoreTest, CorruptPagesAreRefused) {
  ASSERT_TRUE(SaveMap(MakeMap(3, 40), Path("m.db")));
  std::string bytes = ReadBytes(Path("m.db"));
  for (size_t i = 4096 + 8; i < bytes.size(); i += 97)
    bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  {
    std::ofstream out(Path("c.db"), std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  EXPECT_THROW(LoadMap(Path("c.db")), LoadError);
  EXPECT_EQ(ReadBytes(Path("c.db")), bytes);
}

TEST_F(MapStoreTest, ForeignFilesAreRefused) {
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(Path("other.db").c_str(), &db), SQLITE_OK);
    sqlite3_exec(db, "CREATE TABLE keyframes(id INTEGER); INSERT INTO keyframes VALUES(1);",
                 nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  try {
    LoadMap(Path("other.db"));
    FAIL() << "accepted a foreign SQLite file";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("not an icgm map"), std::string::npos) << e.what();
  }
  {
    std::ofstream out(Path("text.db"));
    out << "timestamp tx ty tz qx qy qz qw\n";
    for (int i = 0; i < 100; ++i) out << i << " 0 0 0 0 0 0 1\n";
  }
  EXPECT_THROW(LoadMap(Path("text.db")), LoadError);
  EXPECT_THROW(LoadMap(Path("nothing_here.db")), LoadError);
}

TEST_F(MapStoreTest, NewerSchemaIsRefused) {
  ASSERT_TRUE(SaveMap(MakeMap(1, 4), Path("m.db")));
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(Path("m.db").c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  try {
    LoadMap(Path("m.db"));
    FAIL() << "accepted schema 99";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 99"), std::string::npos) << e.what();
  }
}

TEST_F(MapStoreTest, TwoSessionsMergeIntoOneMap) {
  const HybridMap day = MakeMap(4, 8);
  const HybridMap night = MakeMap(5, 6);
  ASSERT_TRUE(SaveMap(day, Path("day.db")));
  ASSERT_TRUE(SaveMap(night, Path("night.db")));
  HybridMap merged = LoadMap(Path("day.db"));
  merged.Merge(LoadMap(Path("night.db")));
  ASSERT_TRUE(SaveMap(merged, Path("merged.db")));
  const HybridMap loaded = LoadMap(Path("merged.db"));
  ExpectIdentical(merged, loaded);
  ASSERT_EQ(loaded.size(), day.size() + night.size());
  ASSERT_EQ(loaded.sessions().size(), 4u);
  EXPECT_EQ(loaded.sessions()[2].name, night.sessions()[0].name);
  EXPECT_EQ(loaded.sessions()[3].last_corrected_id,
            night.sessions()[1].last_corrected_id + day.size());
  for (int k = 0; k < night.size(); ++k) {
    EXPECT_TRUE(
        SameBits(loaded.keyframe(day.size() + k).relative_pose, night.keyframe(k).relative_pose));
    EXPECT_EQ(loaded.keyframe(day.size() + k).session_id, night.keyframe(k).session_id + 2);
  }
  // Word ids of the merged-in session belong to another dictionary: cleared, ours kept.
  EXPECT_EQ(loaded.keyframe(0).word_ids, day.keyframe(0).word_ids);
  EXPECT_FALSE(day.keyframe(0).word_ids.empty());
  EXPECT_TRUE(loaded.keyframe(day.size()).word_ids.empty());
  EXPECT_TRUE(loaded.Validate());
}


// Flips one byte in the middle of the first copy of `stored` in the file at `path`.
void FlipStoredBytes(const std::string& path, const void* stored, size_t bytes) {
  std::string file = ReadBytes(path);
  const size_t at = file.find(std::string(static_cast<const char*>(stored), bytes));
  ASSERT_NE(at, std::string::npos) << "bytes not found in " << path;
  ASSERT_EQ(file.find(std::string(static_cast<const char*>(stored), bytes), at + 1),
            std::string::npos);
  file[at + bytes / 2] = static_cast<char>(file[at + bytes / 2] ^ 0x10);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(file.data(), static_cast<std::streamsize>(file.size()));
}

std::string LoadErrorOf(const std::string& path) {
  try {
    LoadMap(path);
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

TEST_F(MapStoreTest, AByteChangedInsideAStoredRowIsRefusedNamingIt) {
  const HybridMap map = MakeMap(3, 10);
  ASSERT_TRUE(SaveMap(map, Path("m.db")));
  std::string note = "unset";
  ExpectIdentical(map, LoadMap(Path("m.db"), &note));
  EXPECT_EQ(note, "");  // current format: verified, nothing to say
  const std::string pristine = ReadBytes(Path("m.db"));
  // A descriptor byte of keyframe 4: still a well-formed SQLite file and a well-formed row.
  const cv::Mat& d = map.keyframe(4).descriptors;
  FlipStoredBytes(Path("m.db"), d.data, d.total() * d.elemSize());
  const std::string flipped = ReadBytes(Path("m.db"));
  std::string why = LoadErrorOf(Path("m.db"));
  EXPECT_NE(why.find("keyframe 4 (table keyframes): checksum mismatch"), std::string::npos) << why;
  EXPECT_NE(why.find("m.db"), std::string::npos) << why;
  EXPECT_EQ(ReadBytes(Path("m.db")), flipped);  // loads never modify the file
  // A global pose value and a link's relative pose.
  std::ofstream(Path("m.db"), std::ios::binary | std::ios::trunc) << pristine;
  FlipStoredBytes(Path("m.db"), map.keyframe(7).global_pose.matrix().data(), 16 * sizeof(double));
  why = LoadErrorOf(Path("m.db"));
  EXPECT_NE(why.find("keyframe 7 (table keyframes)"), std::string::npos) << why;
  std::ofstream(Path("m.db"), std::ios::binary | std::ios::trunc) << pristine;
  const Link& wheel = map.links().back();
  ASSERT_EQ(wheel.type, LinkType::kWheelOdometry);
  FlipStoredBytes(Path("m.db"), wheel.relative_pose.matrix().data(), 16 * sizeof(double));
  why = LoadErrorOf(Path("m.db"));
  EXPECT_NE(why.find("link " + std::to_string(wheel.from_id) + " -> " +
                     std::to_string(wheel.to_id) + " (table links)"),
            std::string::npos)
      << why;
}

TEST_F(MapStoreTest, MapsOfTheVersionBeforeChecksumsLoadUnverifiedWithANote) {
  const HybridMap map = MakeMap(2, 6);
  ASSERT_TRUE(SaveMap(map, Path("v2.db")));
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(Path("v2.db").c_str(), &db), SQLITE_OK);
  std::string sql;
  for (const char* t : {"sessions", "loops", "keyframes", "links", "keyframe_images"}) {
    sql += std::string("ALTER TABLE ") + t + " DROP COLUMN checksum; ";
  }
  ASSERT_EQ(sqlite3_exec(db, (sql + "PRAGMA user_version = 2; VACUUM;").c_str(), nullptr, nullptr,
                         nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(db);
  sqlite3_close(db);
  std::string note;
  ExpectIdentical(map, LoadMap(Path("v2.db"), &note));
  EXPECT_NE(note.find("format version 2"), std::string::npos) << note;
  EXPECT_NE(note.find("without verifying"), std::string::npos) << note;
  // Saved again, it is the current, checksummed format.
  ASSERT_TRUE(SaveMap(LoadMap(Path("v2.db")), Path("v3.db")));
  ExpectIdentical(map, LoadMap(Path("v3.db"), &note));
  EXPECT_EQ(note, "");
}

}  // namespace
}  // namespace icgm

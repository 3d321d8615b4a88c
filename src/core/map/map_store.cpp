#include "core/map/map_store.h"

#include <signal.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <vector>

namespace icgm {
namespace {

constexpr size_t kKeypointBytes = 7 * 4;

struct DbCloser {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtFinalizer {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Db = std::unique_ptr<sqlite3, DbCloser>;
using Stmt = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

const char* kSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE sessions(id INTEGER PRIMARY KEY, name TEXT NOT NULL, origin BLOB NOT NULL,
                      last_corrected_id INTEGER NOT NULL, checksum INTEGER NOT NULL);
CREATE TABLE loops(id INTEGER PRIMARY KEY, session_id INTEGER NOT NULL, checksum INTEGER NOT NULL);
CREATE TABLE keyframes(id INTEGER PRIMARY KEY, session_id INTEGER NOT NULL,
                       loop_id INTEGER NOT NULL, previous_id INTEGER NOT NULL,
                       stamp_ns INTEGER NOT NULL, relative_pose BLOB NOT NULL,
                       relative_source INTEGER NOT NULL, global_pose BLOB NOT NULL,
                       descriptor_type INTEGER NOT NULL, descriptor_cols INTEGER NOT NULL,
                       descriptors BLOB, keypoints BLOB, points BLOB, word_ids BLOB,
                       checksum INTEGER NOT NULL);
CREATE TABLE links(id INTEGER PRIMARY KEY, from_id INTEGER NOT NULL, to_id INTEGER NOT NULL,
                   type INTEGER NOT NULL, relative_pose BLOB NOT NULL,
                   information BLOB NOT NULL, inliers INTEGER NOT NULL, checksum INTEGER NOT NULL);
CREATE TABLE keyframe_images(id INTEGER PRIMARY KEY, downsample INTEGER NOT NULL,
                             width INTEGER NOT NULL, height INTEGER NOT NULL,
                             intrinsics BLOB NOT NULL, depth_mm BLOB NOT NULL, bgr BLOB,
                             checksum INTEGER NOT NULL);
)sql";

// FNV-1a 64 (on 8-byte little-endian words, then the remaining bytes) over a row's values in
// column order, each value preceded by its SQLite type and its length in bytes. Each step
// (h ^ word) * odd prime is a bijection of h, so a changed byte anywhere in the row, blob or
// integer, always changes the hash.
class RowHash {
 public:
  void Add(int type, const void* data, size_t bytes) {
    const uint64_t header[2] = {static_cast<uint64_t>(type), bytes};
    Mix(header, sizeof(header));
    Mix(data, bytes);
  }
  void AddInt(int64_t v) { Add(SQLITE_INTEGER, &v, sizeof(v)); }
  // Column `col` of a row as read back.
  void AddColumn(sqlite3_stmt* s, int col) {
    const int type = sqlite3_column_type(s, col);
    if (type == SQLITE_INTEGER) {
      AddInt(sqlite3_column_int64(s, col));
    } else if (type == SQLITE_BLOB) {
      const void* data = sqlite3_column_blob(s, col);
      Add(type, data, static_cast<size_t>(sqlite3_column_bytes(s, col)));
    } else if (type == SQLITE_TEXT) {
      const void* data = sqlite3_column_text(s, col);
      Add(type, data, static_cast<size_t>(sqlite3_column_bytes(s, col)));
    } else {
      Add(type, nullptr, 0);
    }
  }
  int64_t value() const { return static_cast<int64_t>(h_); }

 private:
  void Mix(const void* data, size_t bytes) {
    constexpr uint64_t kPrime = 0x100000001b3ULL;
    const auto* p = static_cast<const uint8_t*>(data);
    size_t i = 0;
    for (; i + 8 <= bytes; i += 8) {
      uint64_t word;
      std::memcpy(&word, p + i, 8);
      h_ = (h_ ^ word) * kPrime;
    }
    for (; i < bytes; ++i) h_ = (h_ ^ p[i]) * kPrime;
  }
  uint64_t h_ = 0xcbf29ce484222325ULL;
};

// ---- blobs ----
std::vector<uint8_t> PoseBlob(const Pose3& p) {
  std::vector<uint8_t> b(16 * sizeof(double));
  std::memcpy(b.data(), p.matrix().data(), b.size());
  return b;
}
std::vector<uint8_t> MatBlob(const Mat6& m) {
  std::vector<uint8_t> b(36 * sizeof(double));
  std::memcpy(b.data(), m.data(), b.size());
  return b;
}
std::vector<uint8_t> KeypointBlob(const std::vector<cv::KeyPoint>& kps) {
  std::vector<uint8_t> b(kps.size() * kKeypointBytes);
  uint8_t* p = b.data();
  for (const auto& k : kps) {
    const float f[5] = {k.pt.x, k.pt.y, k.size, k.angle, k.response};
    const int32_t i[2] = {k.octave, k.class_id};
    std::memcpy(p, f, sizeof(f));
    std::memcpy(p + sizeof(f), i, sizeof(i));
    p += kKeypointBytes;
  }
  return b;
}
std::vector<uint8_t> PointBlob(const std::vector<Eigen::Vector3d>& pts) {
  std::vector<uint8_t> b(pts.size() * 3 * sizeof(double));
  for (size_t i = 0; i < pts.size(); ++i) {
    std::memcpy(b.data() + i * 3 * sizeof(double), pts[i].data(), 3 * sizeof(double));
  }
  return b;
}

// ---- writing ----
class Writer {
 public:
  explicit Writer(sqlite3* db) : db_(db) {}
  bool Exec(const char* sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
      error_ = err ? err : "unknown error";
      sqlite3_free(err);
      return false;
    }
    return true;
  }
  Stmt Prepare(const char* sql) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_, sql, -1, &s, nullptr) != SQLITE_OK) error_ = sqlite3_errmsg(db_);
    return Stmt(s);
  }
  // Binds values left to right and steps once.
  bool Run(sqlite3_stmt* s) {
    const bool ok = sqlite3_step(s) == SQLITE_DONE;
    if (!ok) error_ = sqlite3_errmsg(db_);
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
    return ok;
  }
  const std::string& error() const { return error_; }

 private:
  sqlite3* db_;
  std::string error_;
};

// Binds a row's values left to right, hashing them as RowHash::AddColumn will read them back,
// then binds the checksum as the last value and steps once.
class Row {
 public:
  Row(Writer& w, sqlite3_stmt* s) : w_(w), s_(s) {}
  Row& Int(int64_t v) {
    sqlite3_bind_int64(s_, ++col_, v);
    hash_.AddInt(v);
    return *this;
  }
  // No data (an empty vector's data() may be null) is stored as NULL, as SQLite does.
  Row& Blob(const void* data, size_t bytes) {
    if (data == nullptr) {
      sqlite3_bind_null(s_, ++col_);
      hash_.Add(SQLITE_NULL, nullptr, 0);
    } else {
      sqlite3_bind_blob(s_, ++col_, data, static_cast<int>(bytes), SQLITE_TRANSIENT);
      hash_.Add(SQLITE_BLOB, data, bytes);
    }
    return *this;
  }
  Row& Blob(const std::vector<uint8_t>& b) { return Blob(b.data(), b.size()); }
  Row& Mat(const cv::Mat& m) {
    const cv::Mat c = m.isContinuous() ? m : m.clone();
    return Blob(c.empty() ? nullptr : c.data, c.total() * c.elemSize());
  }
  Row& Text(const std::string& t) {
    sqlite3_bind_text(s_, ++col_, t.c_str(), static_cast<int>(t.size()), SQLITE_TRANSIENT);
    hash_.Add(SQLITE_TEXT, t.data(), t.size());
    return *this;
  }
  bool Run() {
    sqlite3_bind_int64(s_, ++col_, hash_.value());
    return w_.Run(s_);
  }

 private:
  Writer& w_;
  sqlite3_stmt* s_;
  int col_ = 0;
  RowHash hash_;
};

std::vector<uint8_t> IntrinsicsBlob(const CameraIntrinsics& k) {
  const double v[4] = {k.fx_px, k.fy_px, k.cx_px, k.cy_px};
  std::vector<uint8_t> b(sizeof(v));
  std::memcpy(b.data(), v, sizeof(v));
  return b;
}

bool WriteImages(Writer& w, sqlite3_stmt* s, int id, const KeyframeImages& images) {
  Row row(w, s);
  row.Int(id).Int(images.downsample).Int(images.depth_mm.cols).Int(images.depth_mm.rows);
  row.Blob(IntrinsicsBlob(images.intrinsics)).Mat(images.depth_mm);
  if (images.bgr.empty()) {
    row.Blob(nullptr, 0);
  } else {
    row.Mat(images.bgr);
  }
  return row.Run();
}

bool WriteAll(Writer& w, const HybridMap& map) {
  const std::string header = "PRAGMA application_id = " + std::to_string(kMapApplicationId) +
                             "; PRAGMA user_version = " + std::to_string(kMapSchemaVersion) +
                             "; PRAGMA journal_mode = MEMORY; PRAGMA synchronous = FULL;";
  if (!w.Exec(header.c_str()) || !w.Exec("BEGIN") || !w.Exec(kSchema)) return false;
  Stmt meta = w.Prepare("INSERT INTO meta VALUES(?, ?)");
  Stmt ses = w.Prepare("INSERT INTO sessions VALUES(?, ?, ?, ?, ?)");
  Stmt loop = w.Prepare("INSERT INTO loops VALUES(?, ?, ?)");
  Stmt kf = w.Prepare("INSERT INTO keyframes VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  Stmt link = w.Prepare("INSERT INTO links VALUES(?, ?, ?, ?, ?, ?, ?, ?)");
  Stmt images = w.Prepare("INSERT INTO keyframe_images VALUES(?, ?, ?, ?, ?, ?, ?, ?)");
  if (!meta || !ses || !loop || !kf || !link || !images) return false;
  sqlite3_bind_text(meta.get(), 1, "writer", -1, SQLITE_STATIC);
  sqlite3_bind_text(meta.get(), 2, "icgm_slam", -1, SQLITE_STATIC);
  if (!w.Run(meta.get())) return false;
  for (const auto& s : map.sessions()) {
    Row row(w, ses.get());
    if (!row.Int(s.id).Text(s.name).Blob(PoseBlob(s.origin)).Int(s.last_corrected_id).Run()) {
      return false;
    }
  }
  for (const auto& l : map.loops()) {
    if (!Row(w, loop.get()).Int(l.id).Int(l.session_id).Run()) return false;
  }
  for (const auto& k : map.keyframes()) {
    Row row(w, kf.get());
    row.Int(k.id).Int(k.session_id).Int(k.loop_id).Int(k.previous_id).Int(k.stamp.nanoseconds());
    row.Blob(PoseBlob(k.relative_pose)).Int(static_cast<int>(k.relative_source));
    row.Blob(PoseBlob(k.global_pose));
    row.Int(k.descriptors.depth() == CV_32F ? 1 : 0).Int(k.descriptors.cols).Mat(k.descriptors);
    row.Blob(KeypointBlob(k.keypoints)).Blob(PointBlob(k.points_m));
    row.Blob(k.word_ids.data(), k.word_ids.size() * sizeof(int32_t));
    if (!row.Run()) return false;
    if (!k.images.empty() && !WriteImages(w, images.get(), k.id, k.images)) return false;
  }
  int link_id = 0;
  for (const auto& l : map.links()) {
    Row row(w, link.get());
    row.Int(link_id++).Int(l.from_id).Int(l.to_id).Int(static_cast<int>(l.type));
    row.Blob(PoseBlob(l.relative_pose)).Blob(MatBlob(l.information)).Int(l.inliers);
    if (!row.Run()) return false;
  }
  return w.Exec("COMMIT");
}

// Removes "<path>.tmp.<pid>" files left by saves whose process no longer exists (killed during a
// save); a save still running in another process keeps its file.
void RemoveStaleTemporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string pid_text = name.substr(prefix.size());
    if (pid_text.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::strtol(pid_text.c_str(), nullptr, 10);
    const bool alive = pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
    if (!alive) {
      std::error_code remove_ec;
      fs::remove(it->path(), remove_ec);
    }
  }
}

}  // namespace

Status CheckMapWritable(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return Status::Error("no map path given");
  std::error_code ec;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) {
    return Status::Error("cannot save map to '" + path + "': folder '" + dir.string() +
                         "' does not exist");
  }
  if (::access(dir.c_str(), W_OK) != 0) {
    return Status::Error("cannot save map to '" + path + "': folder '" + dir.string() +
                         "' is not writable");
  }
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st)) {
    if (fs::is_directory(st)) {
      return Status::Error("cannot save map to '" + path + "': it is a folder");
    }
    // A file without any write permission is protected from replacement, even for a user (such
    // as root) whom the permissions would not stop: a save renames over it.
    const fs::perms write = fs::perms::owner_write | fs::perms::group_write |
                            fs::perms::others_write;
    if ((st.permissions() & write) == fs::perms::none || ::access(path.c_str(), W_OK) != 0) {
      return Status::Error("map file '" + path + "' is read-only; it is not replaced (make it "
                           "writable or save elsewhere)");
    }
  }
  return Status::Ok();
}

Status SaveMap(const HybridMap& map, const std::string& path) {
  namespace fs = std::filesystem;
  const Status writable = CheckMapWritable(path);
  if (!writable.ok()) return writable;
  RemoveStaleTemporaries(path);
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  fs::remove(tmp, ec);
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(tmp.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
    sqlite3_close(raw);
    fs::remove(tmp, ec);
    return Status::Error("cannot save map to '" + path + "': " + why);
  }
  Db db(raw);
  Writer writer(db.get());
  const bool written = WriteAll(writer, map);
  const std::string why = writer.error();
  db.reset();
  if (!written) {
    fs::remove(tmp, ec);
    return Status::Error("cannot save map to '" + path + "': " + why);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string rename_error = ec.message();
    fs::remove(tmp, ec);
    return Status::Error("cannot save map to '" + path + "': rename failed: " + rename_error);
  }
  return Status::Ok();
}

namespace {

// ---- reading ----
class Reader {
 public:
  Reader(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  [[noreturn]] void Fail(const std::string& why) const {
    throw LoadError("map '" + path_ + "' refused: " + why);
  }
  Stmt Prepare(const std::string& sql) const {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
      Fail(sqlite3_errmsg(db_));
    }
    return Stmt(s);
  }
  // "SELECT <columns>[, checksum] FROM <table> ORDER BY id": the stored checksum follows the
  // columns when the file has them (version 3 on).
  Stmt Select(const std::string& columns, const std::string& table) const {
    return Prepare("SELECT " + columns + (checksums_ ? ", checksum" : "") + " FROM " + table +
                   " ORDER BY id");
  }
  void set_checksums(bool on) { checksums_ = on; }
  // With checksums, column `columns` holds the checksum of columns 0..columns-1 as written.
  void CheckRow(sqlite3_stmt* s, int columns, const std::string& table,
                const std::string& what) const {
    if (!checksums_) return;
    RowHash hash;
    for (int c = 0; c < columns; ++c) hash.AddColumn(s, c);
    if (sqlite3_column_type(s, columns) != SQLITE_INTEGER ||
        sqlite3_column_int64(s, columns) != hash.value()) {
      Fail(what + " (table " + table + "): checksum mismatch, the stored row was altered or " +
           "damaged after it was written");
    }
  }
  // Steps; true on a row, false when done; throws on an error.
  bool Step(sqlite3_stmt* s) const {
    const int rc = sqlite3_step(s);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    Fail(sqlite3_errmsg(db_));
  }
  int64_t Scalar(const char* sql) const {
    Stmt s = Prepare(sql);
    if (!Step(s.get())) Fail(std::string("no result for ") + sql);
    return sqlite3_column_int64(s.get(), 0);
  }
  // Copies a blob column of exactly `bytes` bytes.
  void Blob(sqlite3_stmt* s, int col, void* out, size_t bytes, const std::string& what) const {
    const size_t n = static_cast<size_t>(sqlite3_column_bytes(s, col));
    if (n != bytes) {
      Fail(what + " has " + std::to_string(n) + " bytes, expected " + std::to_string(bytes));
    }
    if (bytes > 0) std::memcpy(out, sqlite3_column_blob(s, col), bytes);
  }
  Pose3 PoseColumn(sqlite3_stmt* s, int col, const std::string& what) const {
    Pose3 p;
    Blob(s, col, p.matrix().data(), 16 * sizeof(double), what);
    return p;
  }

 private:
  sqlite3* db_;
  std::string path_;
  bool checksums_ = false;
};

// Page size and count from the 100-byte header must match the file size.
void CheckHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 100> h{};
  const auto fail = [&](const std::string& why) {
    throw LoadError("map '" + path + "' refused: " + why);
  };
  if (!in.read(reinterpret_cast<char*>(h.data()), h.size())) {
    fail("file is shorter than an SQLite header (truncated or not a map)");
  }
  if (std::memcmp(h.data(), "SQLite format 3", 16) != 0) fail("not an SQLite database");
  uint32_t page_size = (h[16] << 8) | h[17];
  if (page_size == 1) page_size = 65536;
  const uint32_t pages = (uint32_t{h[28]} << 24) | (h[29] << 16) | (h[30] << 8) | h[31];
  const uintmax_t size = std::filesystem::file_size(path);
  if (page_size < 512 || size % page_size != 0 ||
      (pages != 0 && size != static_cast<uintmax_t>(pages) * page_size)) {
    fail("file size " + std::to_string(size) + " does not match " + std::to_string(pages) +
         " pages of " + std::to_string(page_size) + " bytes (truncated)");
  }
}

std::map<int, KeyframeImages> ReadImages(const Reader& r) {
  std::map<int, KeyframeImages> out;
  Stmt s = r.Select("id, downsample, width, height, intrinsics, depth_mm, bgr", "keyframe_images");
  while (r.Step(s.get())) {
    const int id = sqlite3_column_int(s.get(), 0);
    const std::string what = "keyframe " + std::to_string(id) + " images";
    r.CheckRow(s.get(), 7, "keyframe_images", what);
    KeyframeImages k;
    k.downsample = sqlite3_column_int(s.get(), 1);
    const int width = sqlite3_column_int(s.get(), 2);
    const int height = sqlite3_column_int(s.get(), 3);
    if (k.downsample < 1 || width < 1 || height < 1 || width > 1 << 15 || height > 1 << 15) {
      r.Fail(what + ": bad size");
    }
    double v[4];
    r.Blob(s.get(), 4, v, sizeof(v), what + " intrinsics");
    k.intrinsics.fx_px = v[0];
    k.intrinsics.fy_px = v[1];
    k.intrinsics.cx_px = v[2];
    k.intrinsics.cy_px = v[3];
    k.intrinsics.width_px = width;
    k.intrinsics.height_px = height;
    k.depth_mm = cv::Mat(height, width, CV_16UC1);
    r.Blob(s.get(), 5, k.depth_mm.data, k.depth_mm.total() * k.depth_mm.elemSize(), what + " depth");
    if (sqlite3_column_type(s.get(), 6) != SQLITE_NULL) {
      k.bgr = cv::Mat(height, width, CV_8UC3);
      r.Blob(s.get(), 6, k.bgr.data, k.bgr.total() * k.bgr.elemSize(), what + " colour");
    }
    out[id] = std::move(k);
  }
  return out;
}

}  // namespace

HybridMap LoadMap(const std::string& path, std::string* note) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw LoadError("map '" + path + "' refused: no such file");
  }
  CheckHeader(path);
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  Db db(raw);
  Reader r(db.get(), path);
  if (rc != SQLITE_OK) r.Fail(raw ? sqlite3_errmsg(raw) : "cannot open");
  const int64_t app = r.Scalar("PRAGMA application_id");
  if (app != kMapApplicationId) {
    r.Fail("not an icgm map (application_id " + std::to_string(app) + ")");
  }
  const int64_t version = r.Scalar("PRAGMA user_version");
  if (version < kMapOldestReadableSchemaVersion || version > kMapSchemaVersion) {
    r.Fail("schema version " + std::to_string(version) + ", this build reads " +
           std::to_string(kMapOldestReadableSchemaVersion) + " to " +
           std::to_string(kMapSchemaVersion));
  }
  r.set_checksums(version >= kMapFirstChecksummedSchemaVersion);
  if (note != nullptr) {
    note->clear();
    if (version < kMapFirstChecksummedSchemaVersion) {
      *note = "map '" + path + "' has format version " + std::to_string(version) +
              ", written before rows carried checksums: loaded without verifying its contents" +
              " (saving it writes version " + std::to_string(kMapSchemaVersion) + ")";
    }
  }
  {
    Stmt check = r.Prepare("PRAGMA quick_check");
    while (r.Step(check.get())) {
      const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(check.get(), 0));
      const std::string line = text ? text : "";
      if (line != "ok") r.Fail("integrity check: " + line);
    }
  }
  HybridMap map;
  const auto restore = [&](const Status& s) {
    if (!s.ok()) r.Fail(s.reason());
  };
  Stmt ses = r.Select("id, name, origin, last_corrected_id", "sessions");
  while (r.Step(ses.get())) {
    SessionRecord s;
    s.id = sqlite3_column_int(ses.get(), 0);
    r.CheckRow(ses.get(), 4, "sessions", "session " + std::to_string(s.id));
    const auto* name = reinterpret_cast<const char*>(sqlite3_column_text(ses.get(), 1));
    s.name = name ? name : "";
    s.origin = r.PoseColumn(ses.get(), 2, "session origin");
    s.last_corrected_id = sqlite3_column_int(ses.get(), 3);
    restore(map.RestoreSession(s));
  }
  Stmt loops = r.Select("id, session_id", "loops");
  std::vector<LoopRecord> loop_records;
  while (r.Step(loops.get())) {
    LoopRecord l;
    l.id = sqlite3_column_int(loops.get(), 0);
    r.CheckRow(loops.get(), 2, "loops", "loop " + std::to_string(l.id));
    l.session_id = sqlite3_column_int(loops.get(), 1);
    if (l.id != static_cast<int>(loop_records.size())) r.Fail("loop ids are not dense");
    loop_records.push_back(l);
  }
  // Version 2 added the optional keyframe images; version-1 maps have none.
  std::map<int, KeyframeImages> images;
  if (version >= 2) images = ReadImages(r);
  Stmt kfs = r.Select(
      "id, session_id, loop_id, previous_id, stamp_ns, relative_pose, relative_source,"
      " global_pose, descriptor_type, descriptor_cols, descriptors, keypoints, points, word_ids",
      "keyframes");
  while (r.Step(kfs.get())) {
    sqlite3_stmt* s = kfs.get();
    Keyframe k;
    k.id = sqlite3_column_int(s, 0);
    const std::string what = "keyframe " + std::to_string(k.id);
    r.CheckRow(s, 14, "keyframes", what);
    k.session_id = sqlite3_column_int(s, 1);
    k.loop_id = sqlite3_column_int(s, 2);
    k.previous_id = sqlite3_column_int(s, 3);
    k.stamp = Time::FromNanoseconds(sqlite3_column_int64(s, 4));
    k.relative_pose = r.PoseColumn(s, 5, what + " relative pose");
    const int source = sqlite3_column_int(s, 6);
    if (source < 0 || source > 2) r.Fail(what + ": bad relative pose source");
    k.relative_source = static_cast<RelativePoseSource>(source);
    k.global_pose = r.PoseColumn(s, 7, what + " global pose");
    const int type = sqlite3_column_int(s, 8);
    const int cols = sqlite3_column_int(s, 9);
    if ((type != 0 && type != 1) || cols < 0 || cols > 65536) r.Fail(what + ": bad descriptors");
    const size_t n = static_cast<size_t>(sqlite3_column_bytes(s, 11)) / kKeypointBytes;
    k.keypoints.resize(n);
    std::vector<uint8_t> kp_bytes(n * kKeypointBytes);
    r.Blob(s, 11, kp_bytes.data(), kp_bytes.size(), what + " keypoints");
    for (size_t i = 0; i < n; ++i) {
      float f[5];
      int32_t in[2];
      std::memcpy(f, &kp_bytes[i * kKeypointBytes], sizeof(f));
      std::memcpy(in, &kp_bytes[i * kKeypointBytes + sizeof(f)], sizeof(in));
      k.keypoints[i] = cv::KeyPoint(f[0], f[1], f[2], f[3], f[4], in[0], in[1]);
    }
    k.descriptors = cv::Mat(static_cast<int>(n), cols, type == 1 ? CV_32F : CV_8U);
    r.Blob(s, 10, k.descriptors.data, k.descriptors.total() * k.descriptors.elemSize(),
           what + " descriptors");
    k.points_m.resize(n);
    std::vector<double> pts(n * 3);
    r.Blob(s, 12, pts.data(), pts.size() * sizeof(double), what + " points");
    for (size_t i = 0; i < n; ++i)
      k.points_m[i] = Eigen::Vector3d(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
    const size_t word_bytes = static_cast<size_t>(sqlite3_column_bytes(s, 13));
    if (word_bytes != 0) {
      k.word_ids.resize(n);
      r.Blob(s, 13, k.word_ids.data(), n * sizeof(int32_t), what + " word ids");
    }
    const auto stored = images.find(k.id);
    if (stored != images.end()) {
      k.images = stored->second;
      images.erase(stored);
    }
    if (k.loop_id >= 0 && k.loop_id < static_cast<int>(loop_records.size())) {
      loop_records[k.loop_id].keyframe_ids.push_back(k.id);
    }
    restore(map.RestoreKeyframe(std::move(k)));
  }
  if (!images.empty()) {
    r.Fail("images of keyframe " + std::to_string(images.begin()->first) + ", which is not in the map");
  }
  for (const auto& l : loop_records) restore(map.RestoreLoop(l));
  Stmt links = r.Select("id, from_id, to_id, type, relative_pose, information, inliers", "links");
  while (r.Step(links.get())) {
    sqlite3_stmt* s = links.get();
    Link l;
    l.from_id = sqlite3_column_int(s, 1);
    l.to_id = sqlite3_column_int(s, 2);
    r.CheckRow(s, 7, "links",
               "link " + std::to_string(l.from_id) + " -> " + std::to_string(l.to_id));
    const int type = sqlite3_column_int(s, 3);
    if (type < 0 || type > 2) r.Fail("link with bad type " + std::to_string(type));
    l.type = static_cast<LinkType>(type);
    l.relative_pose = r.PoseColumn(s, 4, "link pose");
    r.Blob(s, 5, l.information.data(), 36 * sizeof(double), "link information");
    l.inliers = sqlite3_column_int(s, 6);
    restore(map.RestoreLink(l));
  }
  restore(map.Validate());
  map.ResumeLast();
  return map;
}

}  // namespace icgm

// Persistence of the hybrid map as an SQLite database.
//  - Identified by PRAGMA application_id = kMapApplicationId ('ICGM') and versioned by
//    PRAGMA user_version = kMapSchemaVersion; any other SQLite file is refused.
//  - Saves are transactional: the whole map is written to "<path>.tmp.<pid>" in the same
//    directory, committed with synchronous=FULL, then renamed over <path> (atomic on POSIX), so
//    an interrupted save never leaves a half-written map at <path>. A save first removes
//    "<path>.tmp.<pid>" files of processes that no longer exist (a save that was killed).
//  - A read-only file at <path> (no write permission bit) is never replaced: the save fails.
//  - Loads open the file read-only; a truncated file (header page count vs file size), a failed
//    PRAGMA quick_check, or any malformed row is refused with a LoadError naming the file and the
//    cause, and the file is never modified.
//  - Poses, descriptors, keypoints and points are stored as raw little-endian blobs, so
//    load -> save -> load reproduces the map bit for bit.
//  - The dictionary is not stored: MapBuilder::Reset rebuilds it from the keyframes, replaying
//    each keyframe's recorded word ids (no nearest-word search), so it is the same dictionary.
// Tables: sessions(id, name, origin, last_corrected_id), loops(id, session_id),
// keyframes(id, session_id, loop_id, previous_id, stamp_ns, relative_pose, relative_source,
// global_pose, descriptor_type, descriptor_cols, descriptors, keypoints, points, word_ids),
// links(id, from_id, to_id, type, relative_pose, information, inliers), meta(key, value),
// and since version 2 keyframe_images(id, downsample, width, height, intrinsics, depth_mm, bgr):
// the optional downsampled images of a keyframe (Keyframe::images). Version-1 maps still load
// (their keyframes have no images).
// Since version 3 every row of sessions, loops, keyframes, links and keyframe_images ends with a
// `checksum` column: a 64-bit FNV-1a hash (on 8-byte words) of the row's values (type, length
// and bytes of each), verified on load; a mismatch is refused naming the table and the keyframe,
// session, loop or link. Versions 1 and 2 still load, unverified, and say so through LoadMap's
// note. Saves write version 3.
#pragma once

#include <cstdint>
#include <string>

#include "core/common/status.h"
#include "core/map/hybrid_map.h"

namespace icgm {

constexpr int32_t kMapApplicationId = 0x4943474D;  // "ICGM"
constexpr int kMapSchemaVersion = 3;
constexpr int kMapFirstChecksummedSchemaVersion = 3;
constexpr int kMapOldestReadableSchemaVersion = 1;

// Returns a failed Status (the original file, if any, is untouched) on any write error, and when
// CheckMapWritable(path) fails.
Status SaveMap(const HybridMap& map, const std::string& path);
// Whether a save to `path` can replace it: its folder exists and is writable, and an existing
// file there is not read-only. Tools call it before processing starts, so a long run does not
// end without its map.
Status CheckMapWritable(const std::string& path);
// Throws LoadError on a missing, foreign, newer-schema, truncated or corrupt file (including a
// row whose checksum does not match). `note`, when given, is set to a message for the user when
// the file is of a version without checksums (loaded unverified), else cleared.
HybridMap LoadMap(const std::string& path, std::string* note = nullptr);

}  // namespace icgm

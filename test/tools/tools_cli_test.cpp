// The command-line tools as a user runs them: --help on every tool, bad options, and inputs that
// used to give silent wrong results or an abort (unreadable TUM images, read-only map files,
// tiny or empty images).
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tool_test_util.h"

namespace icgm::tools::testing {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> Tools() {
  std::vector<std::string> tools;
  std::stringstream list(ICGM_TOOLS);
  for (std::string t; std::getline(list, t, ',');) {
    if (!t.empty()) tools.push_back(t);
  }
  return tools;
}

class ToolsCliTest : public ToolTest {};

TEST_F(ToolsCliTest, EveryToolPrintsUsageWithHelpAndExitsZero) {
  ASSERT_GE(Tools().size(), 10u) << ICGM_TOOLS;
  for (const std::string& tool : Tools()) {
    ASSERT_TRUE(fs::exists(std::string(ICGM_TOOL_DIR) + "/" + tool)) << tool << " not built";
    for (const char* flag : {"--help", "-h"}) {
      const ToolRun r = Run(tool, {flag});
      EXPECT_EQ(r.exit_code, 0) << tool << " " << flag << ": " << Describe(r);
      EXPECT_EQ(r.out.rfind("usage: " + tool, 0), 0u) << tool << ": " << Describe(r);
      EXPECT_TRUE(r.err.empty()) << tool << ": " << Describe(r);
    }
    // --help wins over anything else on the line, even an unknown option.
    const ToolRun mixed = Run(tool, {"--no-such-option", "--help"});
    EXPECT_EQ(mixed.exit_code, 0) << tool << ": " << Describe(mixed);
  }
}

TEST_F(ToolsCliTest, EveryToolRejectsAnUnknownOptionWithUsage) {
  for (const std::string& tool : Tools()) {
    const ToolRun r = Run(tool, {"--no-such-option"});
    EXPECT_EQ(r.exit_code, 2) << tool << ": " << Describe(r);
    EXPECT_NE(r.err.find(tool + ": unknown option --no-such-option"), std::string::npos)
        << tool << ": " << Describe(r);
    EXPECT_NE(r.err.find("usage: " + tool), std::string::npos) << tool << ": " << Describe(r);
  }
}

// A textured 640x480 frame (blocks of random grey levels: corners for ORB) and flat depth at
// 2 m, as a TUM folder of `n` identical frames; frame `bad` gets an unreadable colour image.
void WriteTumFolder(const fs::path& dir, int n, int bad) {
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  cv::RNG rng(7);
  cv::Mat small(30, 40, CV_8UC3);
  rng.fill(small, cv::RNG::UNIFORM, 0, 255);
  cv::Mat bgr;
  cv::resize(small, bgr, cv::Size(640, 480), 0, 0, cv::INTER_NEAREST);
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(10000));  // 5000 per metre (TUM)
  std::ofstream rgb_txt(dir / "rgb.txt"), depth_txt(dir / "depth.txt");
  rgb_txt << "# colour images\n";
  depth_txt << "# depth images\n";
  for (int i = 0; i < n; ++i) {
    const std::string stamp = std::to_string(1000 + i) + ".000000";
    const std::string name = std::to_string(i) + ".png";
    if (i == bad) {
      std::ofstream(dir / "rgb" / name) << "not a png";
    } else {
      ASSERT_TRUE(cv::imwrite((dir / "rgb" / name).string(), bgr));
    }
    ASSERT_TRUE(cv::imwrite((dir / "depth" / name).string(), depth));
    rgb_txt << stamp << " rgb/" << name << "\n";
    depth_txt << stamp << " depth/" << name << "\n";
  }
}

size_t TrajectoryPoses(const std::string& path) {
  std::ifstream in(path);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty() && line[0] != '#';
  return n;
}

TEST_F(ToolsCliTest, SlamOfflineSkipsAndCountsAnUnreadableTumImage) {
  WriteTumFolder(dir_ / "tum", 6, 3);
  const ToolRun r =
      Run("icgm_slam_offline", {"--tum", Path("tum"), "--camera", "config/camera/tum_fr1.yaml",
                                "--trajectory", Path("traj.txt")});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_NE(r.err.find("frame 3 skipped"), std::string::npos) << Describe(r);
  EXPECT_NE(r.err.find("rgb/3.png"), std::string::npos) << Describe(r);
  EXPECT_NE(r.out.find("skipped 1 unreadable frames"), std::string::npos) << Describe(r);
  // The frames after the bad one were processed.
  EXPECT_EQ(TrajectoryPoses(Path("traj.txt")), 5u) << ReadText(Path("traj.txt"));
}

TEST_F(ToolsCliTest, MonoVoSkipsAndCountsAnUnreadableTumImage) {
  WriteTumFolder(dir_ / "tum", 6, 3);
  const ToolRun r = Run("icgm_mono_vo", {"--tum", Path("tum"), "--camera",
                                         "config/camera/tum_fr1.yaml"});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_NE(r.err.find("frame 3 skipped"), std::string::npos) << Describe(r);
  EXPECT_NE(r.err.find("rgb/3.png"), std::string::npos) << Describe(r);
  EXPECT_NE(r.out.find("skipped              1 unreadable frames"), std::string::npos)
      << Describe(r);
  // The skipped frame is not a frame of the odometry, so not one without a pose.
  EXPECT_NE(r.out.find("frames               5,"), std::string::npos) << Describe(r);
}

// A camera file with a typo, in its `camera` or its `depth_camera` section, is refused by every
// tool that reads it, naming the key, whether or not the tool uses that section.
TEST_F(ToolsCliTest, EveryToolReadingACameraFileRefusesATypoAnywhereInIt) {
  WriteTumFolder(dir_ / "tum", 3, -1);
  const std::string camera =
      "camera: {fx_px: 517.3, fy_px: 516.5, cx_px: 318.6, cy_px: 255.3, width_px: 640,\n"
      "         height_px: 480, depth_scale: 5000.0}\n";
  const std::string depth_camera =
      "depth_camera: {fx_px: 575, fy_px: 575, cx_px: 320, cy_px: 240, width_px: 640,\n"
      "               height_px: 480, xm: -0.025}\n";
  std::ofstream(Path("depth_typo.yaml")) << camera << depth_camera;
  std::string colour_typo = camera;
  colour_typo.insert(colour_typo.find('}'), ", readout: 0.02");
  std::ofstream(Path("colour_typo.yaml")) << colour_typo;
  std::ofstream(Path("images.txt")) << Path("tum/rgb/0.png") << "\n" << Path("tum/rgb/1.png") << "\n";
  for (const auto& [file, key] : {std::pair<std::string, std::string>{"depth_typo.yaml", "depth_camera.xm"},
                                  {"colour_typo.yaml", "camera.readout"}}) {
    const std::vector<std::vector<std::string>> runs = {
        {"icgm_slam_offline", "--tum", Path("tum"), "--trajectory", Path("t.txt")},
        {"icgm_mono_vo", "--tum", Path("tum")},
        {"icgm_tum_info", "--tum", Path("tum")},
        {"icgm_place_recognition", "--images", Path("images.txt"), "--out", Path("m.csv")}};
    for (std::vector<std::string> args : runs) {
      const std::string tool = args.front();
      args.erase(args.begin());
      args.insert(args.end(), {"--camera", Path(file)});
      const ToolRun r = Run(tool, args);
      EXPECT_NE(r.exit_code, 0) << tool << " " << file << ": " << Describe(r);
      EXPECT_NE(r.err.find(key), std::string::npos) << tool << ": " << Describe(r);
    }
  }
  EXPECT_FALSE(fs::exists(Path("t.txt")));
}

TEST_F(ToolsCliTest, SlamOfflineRefusesAReadOnlyMapBeforeProcessing) {
  WriteTumFolder(dir_ / "tum", 4, -1);
  std::ofstream(Path("ro.db")) << "an earlier map";
  fs::permissions(Path("ro.db"),
                  fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const ToolRun r =
      Run("icgm_slam_offline", {"--tum", Path("tum"), "--camera", "config/camera/tum_fr1.yaml",
                                "--trajectory", Path("traj.txt"), "--map", Path("ro.db")});
  EXPECT_EQ(r.exit_code, 1) << Describe(r);
  EXPECT_NE(r.err.find("ro.db"), std::string::npos) << Describe(r);
  EXPECT_NE(r.err.find("read-only"), std::string::npos) << Describe(r);
  EXPECT_EQ(ReadText(Path("ro.db")), "an earlier map");
  EXPECT_FALSE(fs::exists(Path("traj.txt"))) << "processing ran before the map was checked";
  // The same run with a writable map works and leaves no temporary file.
  const ToolRun ok =
      Run("icgm_slam_offline", {"--tum", Path("tum"), "--camera", "config/camera/tum_fr1.yaml",
                                "--trajectory", Path("traj.txt"), "--map", Path("rw.db")});
  ASSERT_EQ(ok.exit_code, 0) << Describe(ok);
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  }
}

// icgm_slam_map and icgm_slam_benchmark stop at an unreadable image (they have no skipping
// source): what was built is reported, the progress bar shows where the run stopped, and the
// exit code says the figures cover fewer frames than the folder holds.
TEST_F(ToolsCliTest, SlamMapAndBenchmarkStoppedByAnUnreadableImageExitOne) {
  WriteTumFolder(dir_ / "tum", 6, 3);
  {
    std::ofstream gt(dir_ / "tum" / "groundtruth.txt");
    for (int i = 0; i < 6; ++i) gt << (1000 + i) << ".000000 0 0 0 0 0 0 1\n";
  }
  const std::vector<std::string> common = {"--tum", Path("tum"), "--camera",
                                           "config/camera/tum_fr1.yaml"};
  std::vector<std::string> map_args = common;
  map_args.insert(map_args.end(), {"--map", Path("m.db"), "--trajectory", Path("t.txt")});
  const std::pair<std::string, std::vector<std::string>> runs[] = {{"icgm_slam_map", map_args},
                                                                   {"icgm_slam_benchmark", common}};
  for (const auto& [tool, args] : runs) {
    const ToolRun r = Run(tool, args);
    EXPECT_EQ(r.exit_code, 1) << tool << ": " << Describe(r);
    EXPECT_NE(r.err.find("input ended early after 3 frames"), std::string::npos)
        << tool << ": " << Describe(r);
    EXPECT_NE(r.err.find("rgb/3.png"), std::string::npos) << tool << ": " << Describe(r);
    EXPECT_EQ(r.err.find("100%"), std::string::npos) << tool << ": " << Describe(r);
  }
}

// icgm_slam_map --localization locates a recording in the map of --merge-into and never writes
// that file, as icgm_slam_offline --localization: the same file as --map is refused up front.
TEST_F(ToolsCliTest, SlamMapLocalizationNeverWritesTheLearnedMap) {
  WriteTumFolder(dir_ / "tum", 6, -1);
  const std::vector<std::string> tum = {"--tum",        Path("tum"),
                                        "--camera",     "config/camera/tum_fr1.yaml",
                                        "--trajectory", Path("t.txt")};
  std::vector<std::string> teach = tum;
  teach.insert(teach.end(), {"--map", Path("learned.db")});
  ASSERT_EQ(Run("icgm_slam_map", teach).exit_code, 0);
  const std::string learned = ReadText(Path("learned.db"));
  const auto inode = [&] {
    struct stat st {};
    return ::stat(Path("learned.db").c_str(), &st) == 0 ? st.st_ino : 0;
  };
  const ino_t before = inode();
  std::vector<std::string> onto_itself = tum;
  onto_itself.insert(onto_itself.end(), {"--localization", "--merge-into", Path("learned.db"),
                                         "--map", Path("learned.db")});
  const ToolRun refused = Run("icgm_slam_map", onto_itself);
  EXPECT_EQ(refused.exit_code, 2) << Describe(refused);
  EXPECT_NE(refused.err.find("never writes the learned map"), std::string::npos)
      << Describe(refused);
  std::vector<std::string> elsewhere = tum;
  elsewhere.insert(elsewhere.end(), {"--localization", "--merge-into", Path("learned.db"), "--map",
                                     Path("localized.db")});
  const ToolRun ok = Run("icgm_slam_map", elsewhere);
  EXPECT_EQ(ok.exit_code, 0) << Describe(ok);
  EXPECT_TRUE(fs::exists(Path("localized.db")));
  // Not replaced, not even by an identical copy.
  EXPECT_EQ(inode(), before);
  EXPECT_EQ(ReadText(Path("learned.db")), learned);
}

// An output in a folder that does not exist is an error before the run, not after it (where
// icgm_slam_map used to stop before saving its map).
TEST_F(ToolsCliTest, SlamToolsCheckTheirOutputFoldersBeforeProcessing) {
  WriteTumFolder(dir_ / "tum", 4, -1);
  const std::vector<std::string> tum = {"--tum", Path("tum"), "--camera",
                                        "config/camera/tum_fr1.yaml"};
  const std::string missing = Path("no_such_folder/t.txt");
  std::vector<std::string> map_run = tum, offline_run = tum;
  map_run.insert(map_run.end(), {"--map", Path("m.db"), "--trajectory", missing});
  offline_run.insert(offline_run.end(), {"--trajectory", Path("t.txt"), "--gt-out", missing});
  const std::pair<std::string, std::vector<std::string>> runs[] = {
      {"icgm_slam_map", map_run}, {"icgm_slam_offline", offline_run}};
  for (const auto& [tool, args] : runs) {
    const ToolRun r = Run(tool, args);
    EXPECT_EQ(r.exit_code, 1) << tool << ": " << Describe(r);
    EXPECT_NE(r.err.find("no_such_folder' does not exist"), std::string::npos)
        << tool << ": " << Describe(r);
    EXPECT_TRUE(r.out.empty()) << tool << " processed first: " << Describe(r);
  }
}

// The first number after `key` in `text` (-1 when absent).
double NumberAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  if (at == std::string::npos) return -1.0;
  return std::stod(text.substr(at + key.size()));
}

// Mapping, merging a second recording as a new session, and localizing in the learned map,
// all through the one offline tool on real frames with ground truth.
TEST_F(ToolsCliTest, SlamOfflineMapsMergesAndLocalizesOnFr1Xyz) {
  const std::string tum = std::string(ICGM_SHARED_DATA_DIR) + "/tum_fr1_xyz";
  if (!fs::exists(tum + "/rgb.txt")) GTEST_SKIP() << "no data: " << tum;
  const std::vector<std::string> input = {
      "--tum", tum, "--camera", "config/camera/tum_fr1.yaml", "--max-frames", "400"};
  auto with = [&input](std::vector<std::string> more) {
    more.insert(more.begin(), input.begin(), input.end());
    return more;
  };
  const ToolRun mapped =
      Run("icgm_slam_offline", with({"--trajectory", Path("map.txt"), "--map", Path("a.db")}));
  ASSERT_EQ(mapped.exit_code, 0) << Describe(mapped);
  const double map_keyframes = NumberAfter(mapped.out, "map: ");
  ASSERT_GT(map_keyframes, 3) << Describe(mapped);
  EXPECT_LT(NumberAfter(mapped.out, "\nATE rmse "), 0.03) << Describe(mapped);
  const std::string learned = ReadText(Path("a.db"));

  // The same frames again, as a second session of the map.
  const ToolRun merged =
      Run("icgm_slam_offline", with({"--trajectory", Path("merge.txt"), "--map", Path("b.db"),
                                     "--merge-into", Path("a.db")}));
  ASSERT_EQ(merged.exit_code, 0) << Describe(merged);
  EXPECT_NE(merged.out.find("in 1 sessions"), std::string::npos) << Describe(merged);
  EXPECT_GT(NumberAfter(merged.out, "map: "), map_keyframes) << Describe(merged);

  // Localization finds the learned map's frame by place recognition and never writes it.
  const ToolRun refused =
      Run("icgm_slam_offline", with({"--trajectory", Path("loc.txt"), "--map", Path("a.db"),
                                     "--localization", Path("a.db")}));
  EXPECT_EQ(refused.exit_code, 2) << Describe(refused);
  const ToolRun localized =
      Run("icgm_slam_offline", with({"--trajectory", Path("loc.txt"), "--map", Path("loc.db"),
                                     "--localization", Path("a.db")}));
  ASSERT_EQ(localized.exit_code, 0) << Describe(localized);
  EXPECT_GT(NumberAfter(localized.out, "loop closures, "), 0) << Describe(localized);
  EXPECT_LT(NumberAfter(localized.out, "\nATE rmse "), 0.05) << Describe(localized);
  EXPECT_EQ(ReadText(Path("a.db")), learned) << "localization changed the learned map";
  for (const char* needs_map : {"--merge-into", "--localization"}) {
    const ToolRun r =
        Run("icgm_slam_offline", with({"--trajectory", Path("x.txt"), needs_map, Path("a.db")}));
    EXPECT_EQ(r.exit_code, 2) << needs_map << ": " << Describe(r);
    EXPECT_NE(r.err.find("needs --map"), std::string::npos) << Describe(r);
  }
}

TEST_F(ToolsCliTest, MapExportWritesTheProductsOfASavedMap) {
  WriteTumFolder(dir_ / "tum", 3, -1);
  const ToolRun map =
      Run("icgm_slam_offline", {"--tum", Path("tum"), "--camera", "config/camera/tum_fr1.yaml",
                                "--trajectory", Path("traj.txt"), "--map", Path("m.db")});
  ASSERT_EQ(map.exit_code, 0) << Describe(map);
  // A wrong cloud extension is refused before any work.
  const ToolRun bad = Run("icgm_map_export", {Path("m.db"), "--pcd", Path("cloud.xyz")});
  EXPECT_EQ(bad.exit_code, 2) << Describe(bad);
  EXPECT_NE(bad.err.find("--pcd needs a file name ending in .pcd"), std::string::npos)
      << Describe(bad);
  // An output in a folder that does not exist is refused before the map is even loaded.
  for (const std::string flag : {"--pcd", "--ply", "--grid"}) {
    const std::string out =
        Path("no_such_folder/cloud") + (flag == "--grid" ? "" : "." + flag.substr(2));
    const ToolRun missing = Run("icgm_map_export", {Path("m.db"), flag, out});
    EXPECT_EQ(missing.exit_code, 1) << Describe(missing);
    EXPECT_NE(missing.err.find("no_such_folder' does not exist"), std::string::npos)
        << Describe(missing);
    EXPECT_EQ(missing.out.find("keyframes"), std::string::npos) << Describe(missing);
  }
  // One keyframe confirms none of its points: nothing static to write.
  const ToolRun none = Run("icgm_map_export", {Path("m.db"), "--pcd", Path("cloud.pcd")});
  EXPECT_EQ(none.exit_code, 1) << Describe(none);
  EXPECT_NE(none.err.find("no points to write"), std::string::npos) << Describe(none);
  // Without the check: the flat wall 2 m in front, voxel filtered, and the grid files.
  const ToolRun all =
      Run("icgm_map_export", {Path("m.db"), "--all-points", "--pcd", Path("cloud.pcd"), "--ply",
                              Path("cloud.ply"), "--grid", Path("grid"), "--voxel-m", "0.05"});
  ASSERT_EQ(all.exit_code, 0) << Describe(all);
  EXPECT_NE(all.out.find("with depth images"), std::string::npos) << Describe(all);
  for (const char* file : {"cloud.pcd", "cloud.ply", "grid.pgm", "grid.yaml"}) {
    EXPECT_TRUE(fs::exists(Path(file))) << file << ": " << Describe(all);
  }
  EXPECT_NE(ReadText(Path("grid.yaml")).find("image: grid.pgm"), std::string::npos);
  // Readable clouds: the headers announce the points the tool reports.
  const std::string pcd = ReadText(Path("cloud.pcd")), ply = ReadText(Path("cloud.ply"));
  const double points = NumberAfter(all.out, "wrote " + Path("cloud.pcd") + ": ");
  EXPECT_GT(points, 0.0) << Describe(all);
  EXPECT_EQ(pcd.rfind("# .PCD v0.7", 0), 0u);
  EXPECT_EQ(NumberAfter(pcd, "\nPOINTS "), points);
  EXPECT_NE(pcd.find("\nDATA binary\n"), std::string::npos);
  EXPECT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_EQ(NumberAfter(ply, "element vertex "), points);
}

// Splits one CSV line (no quoted commas in the fields read here).
std::vector<std::string> CsvFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
  return fields;
}

TEST_F(ToolsCliTest, SlamOfflineReportsTheEvidenceChoicePerFrame) {
  // The simulated hand-held crowd with the crowd profile (select_by_evidence): every frame's
  // winner and its inliers on the walkers (simulator's masks) in frames.csv, every judged
  // hypothesis in hypotheses.csv.
  const ToolRun r = Run("icgm_slam_offline",
                        {"--sim", "config/sim/handheld_crowd.yaml", "--sim-seed", "1", "--config",
                         "config/odometry_handheld_crowd.yaml", "--max-frames", "40",
                         "--trajectory", Path("traj.txt"), "--report", Path("report")});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  std::ifstream frames(Path("report/frames.csv")), hypotheses(Path("report/hypotheses.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(frames, line));
  const std::vector<std::string> header = CsvFields(line);
  const auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const size_t kind = column("chosen_kind"), score = column("chosen_score"),
               runner_up = column("runner_up_score"), inliers = column("chosen_inliers"),
               on_walkers = column("chosen_dynamic_inliers"), count = column("hypotheses");
  ASSERT_LT(runner_up, header.size()) << line;
  // Per frame (index 0 first): the winner's kind, score, inliers and walker inliers.
  std::vector<std::vector<std::string>> winners;
  size_t chosen_frames = 0, walker_inliers = 0, several = 0;
  for (size_t frame = 0; std::getline(frames, line); ++frame) {
    const std::vector<std::string> f = CsvFields(line);
    ASSERT_GT(f.size(), runner_up) << line;
    winners.push_back(f);
    if (f[kind] == "none") continue;
    ++chosen_frames;
    several += std::stoi(f[count]) > 1;
    // Evidence margin 0: the winner has the best score.
    if (f[runner_up] != "nan") {
      EXPECT_GE(std::stod(f[score]), std::stod(f[runner_up])) << line;
    }
    EXPECT_LE(std::stol(f[on_walkers]), std::stol(f[inliers])) << line;
    EXPECT_GE(std::stol(f[on_walkers]), 0) << "masks are known in the simulator: " << line;
    walker_inliers += std::stoul(f[on_walkers]);
  }
  ASSERT_EQ(winners.size(), 40u);
  EXPECT_GE(chosen_frames, 35u) << "every registered frame makes a choice";
  EXPECT_GE(several, chosen_frames / 2) << "most frames have more than one hypothesis";
  EXPECT_GT(walker_inliers, 0u) << "walkers fill part of the view from the start";
  // hypotheses.csv: the row marked chosen is the winner named in frames.csv.
  ASSERT_TRUE(std::getline(hypotheses, line));
  EXPECT_EQ(line,
            "frame,reference,index,kind,chosen,inliers,dynamic_inliers,depth_agreeing,"
            "edges_agreeing,score,prediction_distance,median_depth_m,tx_m,ty_m,tz_m,rx_rad,"
            "ry_rad,rz_rad");
  size_t rows = 0, chosen_rows = 0, predicted_rows = 0;
  while (std::getline(hypotheses, line)) {
    const std::vector<std::string> h = CsvFields(line);
    ASSERT_EQ(h.size(), 18u) << line;
    if (h[3] == "predicted") {
      EXPECT_EQ(h[2], "-1") << line;
      EXPECT_EQ(h[4], "0") << line;
      ++predicted_rows;
      continue;
    }
    ++rows;
    if (h[4] != "1") continue;
    ++chosen_rows;
    const size_t frame = std::stoul(h[0]);
    ASSERT_GE(frame, 1u);  // the first frame has nothing to register to
    ASSERT_LT(frame, winners.size());
    const std::vector<std::string>& w = winners[frame];
    EXPECT_EQ(h[3], w[kind]) << line;
    EXPECT_EQ(h[5], w[inliers]) << line;
    EXPECT_EQ(h[6], w[on_walkers]) << line;
  }
  EXPECT_EQ(chosen_rows, chosen_frames);
  EXPECT_GT(rows, chosen_rows);
  // The crowd profile predicts each motion (velocity_prior) from the second step on.
  EXPECT_GE(predicted_rows + 2, chosen_rows);
}

// Images too small for feature detection, and files that are no image at all.
void WriteBadImages(const fs::path& dir) {
  ASSERT_TRUE(cv::imwrite((dir / "tiny.png").string(), cv::Mat(1, 1, CV_8UC3, cv::Scalar(90))));
  ASSERT_TRUE(cv::imwrite((dir / "small.png").string(), cv::Mat(8, 12, CV_8UC3, cv::Scalar(90))));
  std::ofstream(dir / "empty.png");  // zero bytes
  cv::RNG rng(3);
  cv::Mat small(30, 40, CV_8UC3), image;
  rng.fill(small, cv::RNG::UNIFORM, 0, 255);
  cv::resize(small, image, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
  ASSERT_TRUE(cv::imwrite((dir / "good.png").string(), image));
}

TEST_F(ToolsCliTest, PlaceRecognitionReportsTinyAndEmptyImagesWithoutAborting) {
  WriteBadImages(dir_);
  for (const std::string bad : {"tiny.png", "small.png", "empty.png"}) {
    std::ofstream(Path("list.txt")) << "good.png\n" << bad << "\ngood.png\n";
    for (const std::string robust : {"none", "double"}) {
      const ToolRun r = Run("icgm_place_recognition", {"--images", Path("list.txt"), "--out",
                                                       Path("m.csv"), "--robust", robust});
      EXPECT_EQ(r.signal, 0) << bad << " " << robust << ": " << Describe(r);
      EXPECT_EQ(r.exit_code, 1) << bad << " " << robust << ": " << Describe(r);
      EXPECT_NE(r.err.find(bad), std::string::npos) << bad << " " << robust << ": " << Describe(r);
    }
  }
  // The good images alone still work.
  std::ofstream(Path("list.txt")) << "good.png\ngood.png\ngood.png\n";
  const ToolRun r = Run("icgm_place_recognition",
                        {"--images", Path("list.txt"), "--out", Path("m.csv"), "--robust", "none"});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
}

// An image list's second column is the image's depth: read (and an unreadable one named) when
// the recognizer uses depth, ignored when it does not.
TEST_F(ToolsCliTest, PlaceRecognitionReadsTheDepthColumnOfAnImageList) {
  WriteBadImages(dir_);
  cv::Mat depth(240, 320, CV_16UC1, cv::Scalar(10000));  // 2 m at depth_scale 5000
  ASSERT_TRUE(cv::imwrite(Path("depth.png"), depth));
  std::ofstream(Path("list.txt")) << "good.png depth.png\ngood.png\tdepth.png\n"
                                  << "good.png missing_depth.png\n";
  const ToolRun ignored = Run("icgm_place_recognition", {"--images", Path("list.txt"), "--out",
                                                         Path("m.csv"), "--robust", "none"});
  EXPECT_EQ(ignored.exit_code, 0) << Describe(ignored);
  const ToolRun used =
      Run("icgm_place_recognition",
          {"--images", Path("list.txt"), "--out", Path("m.csv"), "--robust", "none", "--camera",
           "config/camera/tum_fr1.yaml", "--depth-candidates", "3"});
  EXPECT_EQ(used.exit_code, 1) << Describe(used);
  EXPECT_NE(used.err.find("cannot read depth image"), std::string::npos) << Describe(used);
  EXPECT_NE(used.err.find("missing_depth.png"), std::string::npos) << Describe(used);
  std::ofstream(Path("list.txt")) << "good.png depth.png\ngood.png\tdepth.png\n";
  const ToolRun good =
      Run("icgm_place_recognition",
          {"--images", Path("list.txt"), "--out", Path("m.csv"), "--robust", "none", "--camera",
           "config/camera/tum_fr1.yaml", "--geometry", "rgbd", "--depth-candidates", "3"});
  EXPECT_EQ(good.exit_code, 0) << Describe(good);
}

// Two distinct textures seen twice (a, b, a, b): with a ground-truth matrix saying 2 = 0 and
// 3 = 1, the exact revisits score highest and every one is found without a false loop.
TEST_F(ToolsCliTest, PlaceRecognitionScoresAgainstAGroundTruthMatrix) {
  cv::RNG rng(5);
  for (const std::string name : {"a.png", "b.png"}) {
    cv::Mat small(30, 40, CV_8UC3), image;
    rng.fill(small, cv::RNG::UNIFORM, 0, 255);
    cv::resize(small, image, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
    ASSERT_TRUE(cv::imwrite(Path(name), image));
  }
  std::ofstream(Path("list.txt")) << "a.png\nb.png\na.png\nb.png\n";
  cv::Mat truth = cv::Mat::zeros(4, 4, CV_8U);
  truth.at<uchar>(2, 0) = truth.at<uchar>(3, 1) = 255;
  ASSERT_TRUE(cv::imwrite(Path("truth.png"), truth));
  const ToolRun r = Run("icgm_place_recognition",
                        {"--images", Path("list.txt"), "--out", Path("m.csv"), "--robust", "none",
                         "--exclude-recent", "0", "--gt-matrix", Path("truth.png")});
  ASSERT_EQ(r.exit_code, 0) << Describe(r);
  EXPECT_NE(r.out.find("2 of 4 images revisit"), std::string::npos) << Describe(r);
  EXPECT_NE(r.out.find("recall at 100% precision: 100.0%"), std::string::npos) << Describe(r);
  EXPECT_TRUE(cv::imread(Path("m_pr.png")).cols > 0) << "no precision-recall plot";
  // The per-query diagnosis lists each query's hypotheses with their truth.
  const ToolRun diagnosed =
      Run("icgm_place_recognition", {"--images", Path("list.txt"), "--out", Path("m.csv"),
                                     "--robust", "none", "--exclude-recent", "0", "--gt-matrix",
                                     Path("truth.png"), "--diagnose", Path("why.txt")});
  ASSERT_EQ(diagnosed.exit_code, 0) << Describe(diagnosed);
  std::ifstream why(Path("why.txt"));
  const std::string text((std::istreambuf_iterator<char>(why)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("query 2: revisit"), std::string::npos) << text;
  EXPECT_NE(text.find("hypothesis 0 score"), std::string::npos) << text;
  EXPECT_NE(text.find(" true, "), std::string::npos) << text;
  EXPECT_EQ(text.find("MISSED"), std::string::npos) << text;
  // A matrix smaller than the sequence is an error naming it.
  ASSERT_TRUE(cv::imwrite(Path("small_truth.png"), cv::Mat::zeros(3, 3, CV_8U)));
  const ToolRun small =
      Run("icgm_place_recognition", {"--images", Path("list.txt"), "--out", Path("m.csv"),
                                     "--robust", "none", "--gt-matrix", Path("small_truth.png")});
  EXPECT_EQ(small.exit_code, 1) << Describe(small);
  EXPECT_NE(small.err.find("small_truth.png"), std::string::npos) << Describe(small);
  // Both kinds of ground truth at once, or revisit bounds without poses: usage errors.
  const ToolRun both = Run("icgm_place_recognition",
                           {"--images", Path("list.txt"), "--out", Path("m.csv"), "--gt-matrix",
                            Path("truth.png"), "--gt-poses", Path("gt.txt")});
  EXPECT_EQ(both.exit_code, 2) << Describe(both);
  const ToolRun bounds =
      Run("icgm_place_recognition", {"--images", Path("list.txt"), "--out", Path("m.csv"),
                                     "--gt-matrix", Path("truth.png"), "--revisit-m", "0.3"});
  EXPECT_EQ(bounds.exit_code, 2) << Describe(bounds);
}

// Images named by their time stamps get their poses from a TUM trajectory, interpolated across
// motion-capture gaps of up to --gt-max-gap: the image in the 0.15 s gap has a pose by default
// (0.2 s) and none with 0.1 s; the one before the trajectory has none either way.
TEST_F(ToolsCliTest, PlaceRecognitionInterpolatesPosesAcrossShortMocapGaps) {
  cv::RNG rng(5);
  cv::Mat small(30, 40, CV_8UC3), image;
  rng.fill(small, cv::RNG::UNIFORM, 0, 255);
  cv::resize(small, image, cv::Size(320, 240), 0, 0, cv::INTER_NEAREST);
  std::ofstream list(Path("list.txt"));
  for (const std::string stamp : {"99.900", "100.050", "100.180", "100.300", "100.450"}) {
    ASSERT_TRUE(cv::imwrite(Path(stamp + ".png"), image));
    list << stamp << ".png\n";
  }
  list.close();
  std::ofstream gt(Path("gt.txt"));
  gt << "# timestamp tx ty tz qx qy qz qw\n";
  for (int k = 0; k <= 50; ++k) {  // 100 Hz from 100.00 to 100.50 s, none in (100.10, 100.25)
    if (k > 10 && k < 25) continue;
    gt << 100.0 + 0.01 * k << " " << 0.001 * k << " 0 0 0 0 0 1\n";
  }
  gt.close();
  for (const std::string gap : {"", "0.1"}) {
    std::vector<std::string> args = {"--images", Path("list.txt"), "--out",      Path("m.csv"),
                                     "--robust", "none",           "--gt-poses", Path("gt.txt")};
    if (!gap.empty()) args.insert(args.end(), {"--gt-max-gap", gap});
    const ToolRun r = Run("icgm_place_recognition", args);
    ASSERT_EQ(r.exit_code, 0) << Describe(r);
    const std::string unknown = gap.empty() ? "1 images without a ground-truth pose"
                                            : "2 images without a ground-truth pose";
    EXPECT_NE(r.out.find(unknown), std::string::npos) << gap << ": " << Describe(r);
  }
}

// Argument combinations of the subsampled, simulated and table runs that make no sense are
// usage errors naming the option, before any image is read or rendered.
TEST_F(ToolsCliTest, PlaceRecognitionRejectsBadSequenceAndTableArguments) {
  std::ofstream(Path("list.txt")) << "a.png\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--every", "0"}, "--every"},
      {{"--images", Path("list.txt"), "--sim", "config/sim/two_lap_loop.yaml", "--out",
        Path("m.csv")},
       "--images or --sim"},
      {{"--sim", "config/sim/two_lap_loop.yaml", "--gt-poses", Path("gt.txt"), "--out",
        Path("m.csv")},
       "--sim is its own ground truth"},
      {{"--images", Path("list.txt"), "--table", "modes"}, "--table needs ground truth"},
      {{"--sim", "config/sim/two_lap_loop.yaml", "--table", "sizes"}, "--table must be"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--gt-matrix", Path("t.png"),
        "--every", "2"},
       "not with --every"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--geometry", "maybe"}, "--geometry"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--geometry", "rgbd"},
       "--geometry rgbd needs depth"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--unverified-weight", "2"},
       "--unverified-weight"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--diagnose", Path("d.txt")},
       "--diagnose needs ground truth"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--continuation", "maybe"},
       "--continuation must be on or off"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--descriptor-fallback", "1"},
       "--descriptor-fallback must be on or off"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--depth-candidates", "-1"},
       "--depth-candidates must be >= 0"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--rgbd-nearest", "1"},
       "--rgbd-nearest must be on or off"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--rgbd-fallback", "yes"},
       "--rgbd-fallback must be on or off"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--continuation-inliers", "5"},
       "--continuation-inliers must be 0 (off) or >= 8"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--rgbd-agreement", "2"},
       "--rgbd-agreement must be 0 (off) or >= 3"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--geometry", "rgbd", "--camera",
        "config/camera/tum_fr1.yaml"},
       "the image list has no depth column"},
      // The tolerance band: both bounds, at least the revisit bounds, only with poses.
      {{"--sim", "config/sim/two_lap_loop.yaml", "--out", Path("m.csv"), "--soft-m", "1"},
       "--soft-m and --soft-deg go together"},
      {{"--sim", "config/sim/two_lap_loop.yaml", "--out", Path("m.csv"), "--revisit-m", "0.5",
        "--soft-m", "0.3", "--soft-deg", "40"},
       "--soft-m must be >= --revisit-m"},
      {{"--sim", "config/sim/two_lap_loop.yaml", "--out", Path("m.csv"), "--soft-m", "1",
        "--soft-deg", "10"},
       "--soft-deg must be in"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--gt-matrix", Path("t.png"),
        "--soft-m", "1", "--soft-deg", "40"},
       "--soft-m needs --gt-poses or --sim"},
      {{"--sim", "config/sim/two_lap_loop.yaml", "--out", Path("m.csv"), "--gt-max-gap", "0.2"},
       "--gt-max-gap needs --gt-poses"},
      {{"--images", Path("list.txt"), "--out", Path("m.csv"), "--gt-poses", Path("gt.txt"),
        "--gt-max-gap", "0"},
       "--gt-max-gap must be > 0"},
  };
  for (const auto& [args, expected] : cases) {
    const ToolRun r = Run("icgm_place_recognition", args);
    EXPECT_EQ(r.exit_code, 2) << expected << ": " << Describe(r);
    EXPECT_NE(r.err.find(expected), std::string::npos) << Describe(r);
  }
}

TEST_F(ToolsCliTest, IcgmMatchReportsTinyAndEmptyImagesWithoutAborting) {
  WriteBadImages(dir_);
  for (const std::string bad : {"tiny.png", "small.png", "empty.png"}) {
    for (const std::string detector : {"orb", "sift", "akaze", "gftt_orb", "surf"}) {
      const ToolRun r = Run("icgm_match", {Path("good.png"), Path(bad), "--out", Path("m.csv"),
                                           "--detector", detector});
      EXPECT_EQ(r.signal, 0) << bad << " " << detector << ": " << Describe(r);
      EXPECT_EQ(r.exit_code, 1) << bad << " " << detector << ": " << Describe(r);
      EXPECT_NE(r.err.find(bad), std::string::npos)
          << bad << " " << detector << ": " << Describe(r);
    }
  }
  const ToolRun r = Run("icgm_match", {Path("good.png"), Path("good.png"), "--out", Path("m.csv")});
  EXPECT_EQ(r.exit_code, 0) << Describe(r);
}

}  // namespace
}  // namespace icgm::tools::testing

// icgm_map_export: people-free map products from a saved hybrid map. The map's points (the
// stored depth images' pixels, or the ICGM feature points of keyframes without images) are
// checked against the other keyframes (core/map/static_points.h: what another keyframe sees
// through has moved); the static ones are written as a voxel-filtered coloured cloud (PCD / PLY)
// and an occupancy grid in map_server's format. With --people-share SCENARIO.yaml (a map built
// from that simulated scenario) the share of the products on walkers is measured against the
// simulator's dynamic masks at the keyframes' stamps.
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "core/common/progress_bar.h"
#include "core/map/map_export_options.h"
#include "core/map/map_store.h"
#include "core/map/occupancy_grid_io.h"
#include "core/map_export/cloud_export.h"
#include "core/map_export/map_products.h"
#include "core/map_export/people_share.h"
#include "core/map_export/sim_people_truth.h"
#include "core/sim/sim_options.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] =
    "usage: icgm_map_export MAP.db [--pcd OUT.pcd] [--ply OUT.ply] [--grid OUT[.pgm]]\n"
    "                       [--voxel-m 0.02] [--config config/map_export.yaml]\n"
    "                       [--people-share SCENARIO.yaml] [--all-points]\n"
    "  --pcd / --ply: the static map cloud, voxel filtered, coloured (binary PCD / PLY)\n"
    "  --grid: occupancy grid in map_server format (OUT.pgm + OUT.yaml)\n"
    "  --voxel-m: voxel leaf of the cloud in metres (default map_cloud.voxel_m)\n"
    "  --config: dense map product options (default: the built-in defaults, equal to\n"
    "            config/map_export.yaml)\n"
    "  --people-share: for a map of that simulated scenario, the share of the cloud and of\n"
    "                  the occupied grid cells on walkers (ground truth: the dynamic masks)\n"
    "  --all-points: skip the static check (everything the keyframes saw, walkers included)\n"
    "At least one of --pcd, --ply, --grid, --people-share is needed.\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_map_export", kUsage};

std::function<void(size_t, size_t)> BarUpdater(icgm::ProgressBar* bar) {
  return [bar](size_t done, size_t) { bar->Update(done); };
}

void PrintShare(const char* label, const icgm::PeopleShare& s) {
  std::printf("%s: cloud points on people %.2f%% (%zu of %zu), voxels %.2f%% (%zu of %zu), "
              "occupied cells %.2f%% (%zu of %zu)\n",
              label, 100.0 * s.PointShare(), s.points_on_people, s.points, 100.0 * s.VoxelShare(),
              s.voxels_on_people, s.voxels, 100.0 * s.GridShare(), s.occupied_cells_on_people,
              s.occupied_cells);
}

}  // namespace

int main(int argc, char** argv) {
  std::string map_path, pcd, ply, grid_path, config, scenario;
  bool all_points = false;
  double voxel_m = -1.0;
  try {
    icgm::tools::CliArgs args(argc, argv,
                              {"pcd", "ply", "grid", "voxel-m", "config", "people-share"},
                              {"all-points"});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (args.positional().size() != 1) {
      throw std::invalid_argument("expected exactly one map file");
    }
    map_path = args.positional()[0];
    pcd = args.Get("pcd");
    ply = args.Get("ply");
    grid_path = args.Get("grid");
    config = args.Get("config");
    scenario = args.Get("people-share");
    all_points = args.Has("all-points");
    voxel_m = args.GetDouble("voxel-m", -1.0);
    if (args.Has("voxel-m") && !(voxel_m > 0.0 && voxel_m <= 10.0)) {
      throw std::invalid_argument("--voxel-m must be in (0, 10]");
    }
    const auto has_extension = [](const std::string& path, const std::string& ext) {
      return path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
    };
    if (!pcd.empty() && !has_extension(pcd, ".pcd")) {
      throw std::invalid_argument("--pcd needs a file name ending in .pcd");
    }
    if (!ply.empty() && !has_extension(ply, ".ply")) {
      throw std::invalid_argument("--ply needs a file name ending in .ply");
    }
    if (pcd.empty() && ply.empty() && grid_path.empty() && scenario.empty()) {
      throw std::invalid_argument("nothing to do: give --pcd, --ply, --grid or --people-share");
    }
  } catch (const std::invalid_argument& e) {
    return icgm::tools::UsageError(kTool, e.what());
  }
  try {
    icgm::MapExportOptions options;
    if (!config.empty()) options = icgm::LoadMapExportOptions(config);
    if (voxel_m > 0.0) options.cloud.voxel_m = voxel_m;
    if (all_points) options.static_points.enabled = false;
    // Checked before the long part: an output folder that is missing or read-only, or a
    // scenario that does not load, fails at once.
    const std::string problem = icgm::tools::OutputFolderProblem({pcd, ply, grid_path});
    if (!problem.empty()) return icgm::tools::Failure(kTool, problem);
    std::optional<icgm::sim::SimOptions> sim_options;
    if (!scenario.empty()) sim_options = icgm::sim::LoadSimOptions(scenario);

    std::string note;
    const icgm::HybridMap map = icgm::LoadMap(map_path, &note);
    if (!note.empty()) std::fprintf(stderr, "%s: warning: %s\n", kTool.name, note.c_str());
    if (map.empty()) return icgm::tools::Failure(kTool, "map '" + map_path + "' has no keyframes");
    const bool images = icgm::HasKeyframeImages(map);
    std::printf("map %s: %d keyframes, %s\n", map_path.c_str(), map.size(),
                images ? "with depth images" : "feature points only (no stored depth images)");
    // The products the map builder publishes (one core sequence), points kept for the share.
    icgm::MapProducts products;
    icgm::Status built = icgm::Status::Ok();
    {
      icgm::ProgressBar bar(static_cast<size_t>(map.size()), "static check");
      built = icgm::BuildMapProducts(map, options, &products, BarUpdater(&bar),
                                     /*keep_points=*/sim_options.has_value());
      bar.Finish();
    }
    if (!built.ok()) return icgm::tools::Failure(kTool, built.reason());
    const icgm::StaticPointStats& stats = products.stats;
    std::printf("points: %zu, static %zu, removed %zu seen through by other keyframes, %zu not "
                "re-observed\n",
                stats.points, stats.kept, stats.seen_through, stats.unconfirmed);
    const icgm::OccupancyGrid& grid = products.grid;
    std::printf("grid: %d x %d cells of %.3f m, %zu occupied, %zu free, %zu unknown\n",
                grid.width, grid.height, grid.resolution_m,
                grid.Count(icgm::OccupancyGrid::kOccupied), grid.Count(icgm::OccupancyGrid::kFree),
                grid.Count(icgm::OccupancyGrid::kUnknown));
    if (!pcd.empty() || !ply.empty()) {
      const icgm::ColouredCloud cloud = icgm::ToPclCloud(products.cloud);
      for (const std::string& path : {pcd, ply}) {
        if (path.empty()) continue;
        const icgm::Status saved = icgm::SaveCloud(cloud, path);
        if (!saved.ok()) return icgm::tools::Failure(kTool, saved.reason());
        std::printf("wrote %s: %zu points (voxel %.3f m)\n", path.c_str(), cloud.size(),
                    options.cloud.voxel_m);
      }
    }
    if (!grid_path.empty()) {
      std::string pgm, yaml;
      const icgm::Status written = icgm::WriteMapServerGrid(grid, grid_path, &pgm, &yaml);
      if (!written.ok()) return icgm::tools::Failure(kTool, written.reason());
      std::printf("wrote %s and %s\n", pgm.c_str(), yaml.c_str());
    }
    if (sim_options) {
      const icgm::sim::Simulator simulator(*sim_options);
      icgm::SimPeopleTruth truth;
      {
        icgm::ProgressBar bar(static_cast<size_t>(map.size()), "ground truth");
        built = truth.Build(simulator, map, BarUpdater(&bar));
        bar.Finish();
      }
      if (!built.ok()) return icgm::tools::Failure(kTool, built.reason());
      std::vector<Eigen::Vector3d> cameras;
      for (const icgm::Keyframe& k : map.keyframes()) cameras.push_back(k.global_pose.translation());
      const icgm::OccupancyGrid all_grid =
          icgm::BuildOccupancyGrid(map, products.points, options.grid);
      PrintShare("all points",
                 icgm::MeasurePeopleShare(products.points, options.cloud.voxel_m, all_grid, cameras,
                                          options.grid, truth.AsFunction()));
      PrintShare("exported",
                 icgm::MeasurePeopleShare(products.static_points, options.cloud.voxel_m, grid,
                                          cameras, options.grid, truth.AsFunction()));
    }
  } catch (const std::exception& e) {
    return icgm::tools::Failure(kTool, e.what());
  }
  return 0;
}

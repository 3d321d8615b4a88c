// People share on a short clip of the crowded scenario, against the simulator's ground truth:
// keyframes every few frames at the true poses with their rendered depth and colour, as the map
// stores them. Walkers fill a good part of the raw cloud; after the static check at most 1% of
// the cloud points, voxels and occupied grid cells lie on people.
#include <gtest/gtest.h>

#include "core/map/keyframe_images.h"
#include "core/map/map_export_options.h"
#include "core/map_export/people_share.h"
#include "core/map_export/sim_people_truth.h"
#include "core/sim/sim_options.h"
#include "core/sim/simulator.h"

namespace icgm {
namespace {

TEST(PeopleShareTest, CrowdedClipIsPeopleFree) {
  sim::SimOptions options =
      sim::LoadSimOptions(std::string(ICGM_SOURCE_DIR) + "/config/sim/crowded.yaml");
  options.num_frames = 60;
  const sim::Simulator simulator(options);
  HybridMap map;
  Pose3 previous = Pose3::Identity();
  for (size_t i = 0; i < simulator.size(); i += 4) {
    const sim::SimFrame frame = simulator.Render(i);
    Keyframe k;
    k.stamp = frame.stamp;
    k.relative_pose = previous.inverse() * frame.T_world_camera;
    previous = frame.T_world_camera;
    k.images = DownsampleKeyframeImages(frame.bgr, frame.depth_m, simulator.intrinsics(), 4);
    int id = -1;
    ASSERT_TRUE(map.AddKeyframe(std::move(k), Mat6::Identity(), &id).ok());
  }
  SimPeopleTruth truth;
  ASSERT_TRUE(truth.Build(simulator, map).ok());
  const MapExportOptions defaults;
  std::vector<Eigen::Vector3d> cameras;
  for (const Keyframe& k : map.keyframes()) cameras.push_back(k.global_pose.translation());

  const std::vector<MapPoint> all = GatherMapPoints(map, defaults.cloud);
  const OccupancyGrid raw_grid = BuildOccupancyGrid(map, all, defaults.grid);
  const PeopleShare raw = MeasurePeopleShare(all, defaults.cloud.voxel_m, raw_grid, cameras,
                                             defaults.grid, truth.AsFunction());
  // The clip must have walkers in view, or the check below proves nothing.
  EXPECT_GT(raw.PointShare(), 0.03) << raw.points_on_people << " of " << raw.points;
  EXPECT_GT(raw.GridShare(), 0.03);

  const std::vector<MapPoint> kept =
      SelectPoints(all, VerifyStaticPoints(map, all, defaults.static_points));
  const OccupancyGrid grid = BuildOccupancyGrid(map, kept, defaults.grid);
  const PeopleShare share = MeasurePeopleShare(kept, defaults.cloud.voxel_m, grid, cameras,
                                               defaults.grid, truth.AsFunction());
  EXPECT_GT(kept.size(), all.size() / 3);  // the static scene stays
  EXPECT_GT(grid.Count(OccupancyGrid::kOccupied), 100u);
  EXPECT_LE(share.PointShare(), 0.01) << share.points_on_people << " of " << share.points;
  EXPECT_LE(share.VoxelShare(), 0.01) << share.voxels_on_people << " of " << share.voxels;
  EXPECT_LE(share.GridShare(), 0.01)
      << share.occupied_cells_on_people << " of " << share.occupied_cells;
  std::printf("raw: points %.4f voxels %.4f cells %.4f; static: points %.4f voxels %.4f cells %.4f\n",
              raw.PointShare(), raw.VoxelShare(), raw.GridShare(), share.PointShare(),
              share.VoxelShare(), share.GridShare());
}

}  // namespace
}  // namespace icgm

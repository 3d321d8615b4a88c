# Dense, people-free map products with PCL: voxel-filtered static cloud files (PCD / PLY), and
# their share on walkers against the simulator's ground truth.
icgm_core_module(NAME map_export
  SOURCES
    src/core/map_export/cloud_export.cpp
    src/core/map_export/map_products.cpp
    src/core/map_export/people_share.cpp
    src/core/map_export/sim_people_truth.cpp
  DEPS icgm_core_map icgm_core_sim icgm_pcl)

icgm_core_test(NAME map_export
  SOURCES
    test/core/map_export/cloud_export_test.cpp
    test/core/map_export/map_products_test.cpp
    test/core/map_export/people_share_test.cpp
  DEPS icgm_core_map_export icgm_core_map icgm_core_sim)

icgm_core_module(NAME map
  SOURCES
    src/core/map/se3_geodesic.cpp
    src/core/map/pose_average.cpp
    src/core/map/semi_consensus.cpp
    src/core/map/hybrid_map.cpp
    src/core/map/word_index.cpp
    src/core/map/binary_word_index.cpp
    src/core/map/float_word_index.cpp
    src/core/map/visual_dictionary.cpp
    src/core/map/loop_closure.cpp
    src/core/map/pose_graph_optimizer.cpp
    src/core/map/map_builder.cpp
    src/core/map/map_options.cpp
    src/core/map/map_store.cpp
    src/core/map/keyframe_images.cpp
    src/core/map/map_points.cpp
    src/core/map/static_points.cpp
    src/core/map/occupancy_grid.cpp
    src/core/map/occupancy_grid_io.cpp
    src/core/map/map_export_options.cpp
  DEPS icgm_core_common opencv_core SQLite::SQLite3)

# Pose-graph back end (alternative to the eq. 6.4 correction); without Ceres the optimizer is
# compiled out and reports "built without Ceres".
if(TARGET Ceres::ceres)
  target_link_libraries(icgm_core_map PUBLIC Ceres::ceres)
  target_compile_definitions(icgm_core_map PRIVATE ICGM_HAVE_CERES)
endif()

icgm_core_test(NAME map
  SOURCES
    test/core/map/semi_consensus_test.cpp
    test/core/map/pose_average_test.cpp
    test/core/map/hybrid_map_test.cpp
    test/core/map/visual_dictionary_test.cpp
    test/core/map/binary_word_index_test.cpp
    test/core/map/loop_closure_test.cpp
    test/core/map/map_store_test.cpp
    test/core/map/map_options_test.cpp
    test/core/map/pose_graph_optimizer_test.cpp
    test/core/map/keyframe_images_test.cpp
    test/core/map/occupancy_grid_test.cpp
    test/core/map/static_points_test.cpp
  DEPS icgm_core_map opencv_imgcodecs)


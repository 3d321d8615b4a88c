# rostests: simulator bags generated at build time (never committed) replayed through the nodelets.
set(ICGM_TEST_DATA ${CATKIN_DEVEL_PREFIX}/share/icgm_slam/test_data)
set(ICGM_TEST_BAG_CROWDED ${ICGM_TEST_DATA}/crowded_short.bag)
add_custom_command(OUTPUT ${ICGM_TEST_BAG_CROWDED}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND icgm_sim --config ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml --frames 45
          --out ${ICGM_TEST_BAG_CROWDED}
  DEPENDS icgm_sim ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml
  COMMENT "Rendering the crowded test bag")
add_custom_target(icgm_test_bags DEPENDS ${ICGM_TEST_BAG_CROWDED})
if(TARGET tests)
  add_dependencies(tests icgm_test_bags)
endif()

add_library(icgm_rostest_common STATIC EXCLUDE_FROM_ALL test/ros/bag_replayer.cpp)
target_include_directories(icgm_rostest_common PUBLIC ${PROJECT_SOURCE_DIR}/src ${catkin_INCLUDE_DIRS})
target_link_libraries(icgm_rostest_common icgm_ros_bridge ${catkin_LIBRARIES})

add_rostest_gtest(icgm_feature_extraction_rostest test/ros/feature_extraction.test
  test/ros/feature_extraction_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})
target_link_libraries(icgm_feature_extraction_rostest icgm_rostest_common)
add_dependencies(icgm_feature_extraction_rostest icgm_test_bags ${PROJECT_NAME}_generate_messages_cpp)

# ROS bridge: message conversions and rosbag I/O (no ROS master needed).
add_library(icgm_ros_bridge SHARED
  src/ros_bridge/conversions.cpp
  src/ros_bridge/bag_writer.cpp
  src/ros_bridge/bag_reader.cpp
  src/ros_bridge/feature_msgs.cpp
  src/ros_bridge/registration_msgs.cpp
  src/ros_bridge/keyframe_msgs.cpp
  src/ros_bridge/map_msgs.cpp
  src/ros_bridge/map_product_msgs.cpp
  src/ros_bridge/route_msgs.cpp
  src/ros_bridge/odometry_covariance.cpp
  src/ros_bridge/navigation_msgs.cpp
  src/ros_bridge/sim_msgs.cpp
  src/ros_bridge/mono_msgs.cpp
  src/ros_bridge/image_size.cpp)
icgm_unity(icgm_ros_bridge BATCH 7)
target_include_directories(icgm_ros_bridge PUBLIC ${PROJECT_SOURCE_DIR}/src ${catkin_INCLUDE_DIRS})
target_link_libraries(icgm_ros_bridge PUBLIC icgm_core_common icgm_core_dataset icgm_core_icgm icgm_core_registration icgm_core_map icgm_core_nav icgm_core_sim icgm_core_mono ${catkin_LIBRARIES}
  ${OpenCV_LIBS})
add_dependencies(icgm_ros_bridge ${PROJECT_NAME}_generate_messages_cpp)
install(TARGETS icgm_ros_bridge LIBRARY DESTINATION ${ICGM_LIB_DIR})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(icgm_ros_bridge_test
    test/ros_bridge/conversions_test.cpp
    test/ros_bridge/bag_io_test.cpp
    test/ros_bridge/feature_msgs_test.cpp
    test/ros_bridge/registration_msgs_test.cpp
    test/ros_bridge/keyframe_msgs_test.cpp
    test/ros_bridge/route_msgs_test.cpp
    test/ros_bridge/odometry_covariance_test.cpp
    test/ros_bridge/map_product_msgs_test.cpp
    test/ros_bridge/navigation_msgs_test.cpp
    test/ros_bridge/sim_msgs_test.cpp
    test/ros_bridge/obstacle_grid_msgs_test.cpp
    test/ros_bridge/mono_msgs_test.cpp
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  if(TARGET icgm_ros_bridge_test)
    icgm_unity(icgm_ros_bridge_test BATCH 6)
    target_link_libraries(icgm_ros_bridge_test icgm_ros_bridge GTest::gtest_main)
  endif()
endif()

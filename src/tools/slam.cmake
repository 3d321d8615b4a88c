# Offline SLAM front end: ROS-free; the --bag input is compiled in when the ROS bridge exists.
icgm_tool(NAME icgm_slam_offline
  SOURCES src/tools/slam_offline_main.cpp
  DEPS icgm_core_odometry icgm_core_dataset icgm_core_eval)
target_compile_definitions(icgm_slam_offline PRIVATE
  ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
if(TARGET icgm_ros_bridge)
  target_link_libraries(icgm_slam_offline icgm_ros_bridge)
  target_compile_definitions(icgm_slam_offline PRIVATE ICGM_WITH_ROS_BRIDGE)
endif()

# Offline SLAM front end: ROS-free (TUM folders, in-process simulator); the --bag input is
# compiled in when the ROS bridge exists.
icgm_tool(NAME icgm_slam_offline
  SOURCES src/tools/slam_offline_main.cpp src/tools/offline_sources.cpp
          src/tools/dynamic_match_stats.cpp
          src/tools/first_pose_ate.cpp
  DEPS icgm_core_slam icgm_core_odometry icgm_core_dataset icgm_core_eval icgm_core_sim)
target_compile_definitions(icgm_slam_offline PRIVATE
  ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
if(TARGET icgm_ros_bridge)
  target_link_libraries(icgm_slam_offline icgm_ros_bridge)
  target_compile_definitions(icgm_slam_offline PRIVATE ICGM_WITH_ROS_BRIDGE)
endif()

# Loop-closure quality of a saved map against ground truth (recall of revisits, false loops).
icgm_tool(NAME icgm_map_eval SOURCES src/tools/map_eval_main.cpp
  DEPS icgm_core_map icgm_core_eval icgm_core_dataset)

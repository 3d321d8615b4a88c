# Monocular visual odometry offline (TUM folders, in-process simulator; ROS-free); the --bag
# input (the offline front end's bag source) is compiled in when the ROS bridge exists.
icgm_tool(NAME icgm_mono_vo SOURCES src/tools/mono_vo_main.cpp src/tools/offline_sources.cpp
  src/tools/dynamic_match_stats.cpp
  DEPS icgm_core_mono icgm_core_slam icgm_core_dataset icgm_core_eval icgm_core_sim)
target_compile_definitions(icgm_mono_vo PRIVATE ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")
if(TARGET icgm_ros_bridge)
  target_link_libraries(icgm_mono_vo icgm_ros_bridge)
  target_compile_definitions(icgm_mono_vo PRIVATE ICGM_WITH_ROS_BRIDGE)
endif()

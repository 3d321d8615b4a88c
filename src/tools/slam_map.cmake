# Hybrid SLAM (front end + map): offline map building and its benchmark. ROS-free.
icgm_tool(NAME icgm_slam_map
  SOURCES src/tools/slam_map_main.cpp
  DEPS icgm_core_slam icgm_core_eval)
target_compile_definitions(icgm_slam_map PRIVATE ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")

icgm_tool(NAME icgm_slam_benchmark
  SOURCES src/tools/slam_benchmark_main.cpp
  DEPS icgm_core_slam icgm_core_eval)
target_compile_definitions(icgm_slam_benchmark PRIVATE
  ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")

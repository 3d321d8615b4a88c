# Monocular visual odometry offline (TUM folders, in-process simulator; ROS-free).
icgm_tool(NAME icgm_mono_vo SOURCES src/tools/mono_vo_main.cpp
  DEPS icgm_core_mono icgm_core_dataset icgm_core_eval icgm_core_sim)
target_compile_definitions(icgm_mono_vo PRIVATE ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")

# Dataset and evaluation tools (ROS-free).
icgm_tool(NAME icgm_eval_traj
  SOURCES src/tools/eval_traj_main.cpp
  DEPS icgm_core_eval icgm_core_dataset)

icgm_tool(NAME icgm_tum_info
  SOURCES src/tools/tum_info_main.cpp
  DEPS icgm_core_eval icgm_core_dataset)

icgm_tool(NAME icgm_rgbd_scene_stats
  SOURCES src/tools/rgbd_scene_stats_main.cpp
  DEPS icgm_core_sim icgm_core_features icgm_core_eval icgm_core_dataset)

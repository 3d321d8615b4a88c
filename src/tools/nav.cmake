# Navigation benchmark: teach run, then closed-loop repeat runs through localization, the
# obstacle grid and the Navigator on the closed-loop simulator (ROS-free).
icgm_tool(NAME icgm_nav_benchmark SOURCES src/tools/nav_benchmark_main.cpp
  DEPS icgm_core_nav icgm_core_slam icgm_core_sim icgm_core_eval)

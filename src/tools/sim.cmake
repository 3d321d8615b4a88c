# Simulator tools: the renderer benchmark is ROS-free; bag writing and reading need ROS.
icgm_tool(NAME icgm_sim_benchmark SOURCES src/tools/sim_benchmark_main.cpp DEPS icgm_core_sim)
icgm_tool(NAME icgm_sim SOURCES src/tools/sim_main.cpp DEPS icgm_core icgm_ros_bridge ROS)
icgm_tool(NAME icgm_tum_to_bag SOURCES src/tools/tum_to_bag_main.cpp
          DEPS icgm_core icgm_ros_bridge ROS)
icgm_tool(NAME icgm_bag_info SOURCES src/tools/bag_info_main.cpp DEPS icgm_core icgm_ros_bridge ROS)

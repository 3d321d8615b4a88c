# RGB-D sensor tools: CPU per frame of the OpenNI2 driver path (needs the ROS bridge for the
# message conversions the driver nodelet does).
if(TARGET icgm_core_sensor)
  icgm_tool(NAME icgm_openni2_benchmark ROS
    SOURCES src/tools/openni2_benchmark_main.cpp
    DEPS icgm_core_sensor icgm_ros_bridge)
  if(TARGET icgm_openni2_benchmark)
    add_dependencies(icgm_openni2_benchmark icgm_virtual_device)
  endif()
endif()

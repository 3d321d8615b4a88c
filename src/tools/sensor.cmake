# RGB-D sensor tools: a fakenect dump (Kinect v1 recording) from a simulated scenario or a TUM
# folder; CPU per frame of the OpenNI2 driver path (needs the ROS bridge for the
# message conversions the driver nodelet does).
if(TARGET icgm_core_sensor)
  icgm_tool(NAME icgm_fakenect_dump
    SOURCES src/tools/fakenect_dump_main.cpp
    DEPS icgm_core_sensor)
  icgm_tool(NAME icgm_openni2_benchmark ROS
    SOURCES src/tools/openni2_benchmark_main.cpp
    DEPS icgm_core_sensor icgm_ros_bridge)
  if(TARGET icgm_openni2_benchmark)
    add_dependencies(icgm_openni2_benchmark icgm_virtual_device)
    # Also in the OpenNI2 drivers folder's install component, as the program that checks it
    # (launch_scripts/check_openni2_install.sh).
    install(TARGETS icgm_openni2_benchmark RUNTIME DESTINATION ${ICGM_BIN_DIR} COMPONENT icgm_openni2)
    install(TARGETS icgm_ros_bridge LIBRARY DESTINATION ${ICGM_LIB_DIR} COMPONENT icgm_openni2)
  endif()
endif()

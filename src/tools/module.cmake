# Command-line tools. Each area appends its tools in src/tools/<area>.cmake.
foreach(area dataset icgm sim slam map slam_map mono map_export nav sensor)
  if(EXISTS ${PROJECT_SOURCE_DIR}/src/tools/${area}.cmake)
    include(${PROJECT_SOURCE_DIR}/src/tools/${area}.cmake)
  endif()
endforeach()

# The tools as a user runs them (--help, bad options, bad inputs); runs the built binaries:
# every icgm_tool() of this build.
get_property(ICGM_BUILT_TOOLS GLOBAL PROPERTY ICGM_TOOL_TARGETS)
string(REPLACE ";" "," ICGM_BUILT_TOOLS_CSV "${ICGM_BUILT_TOOLS}")
icgm_core_test(NAME tools
  SOURCES test/tools/tools_cli_test.cpp
  DEPS opencv_core opencv_imgcodecs opencv_imgproc)
if(TARGET icgm_tools_test)
  target_include_directories(icgm_tools_test PRIVATE ${PROJECT_SOURCE_DIR}/test/tools)
  target_compile_definitions(icgm_tools_test PRIVATE ICGM_TOOLS="${ICGM_BUILT_TOOLS_CSV}"
    ICGM_TOOL_DIR="$<TARGET_FILE_DIR:icgm_match>")
  add_dependencies(icgm_tools_test ${ICGM_BUILT_TOOLS})
endif()

# icgm_slam_offline on bags missing camera_info or the /tf_static extrinsic (ROS bridge needed).
if(TARGET icgm_ros_bridge)
  icgm_core_test(NAME tools_bag
    SOURCES test/tools/tools_bag_test.cpp
    DEPS icgm_ros_bridge icgm_core_dataset opencv_core opencv_imgproc)
  if(TARGET icgm_tools_bag_test)
    target_include_directories(icgm_tools_bag_test PRIVATE ${PROJECT_SOURCE_DIR}/test/tools)
    target_compile_definitions(icgm_tools_bag_test PRIVATE
      ICGM_TOOL_DIR="$<TARGET_FILE_DIR:icgm_slam_offline>")
    add_dependencies(icgm_tools_bag_test icgm_slam_offline)
  endif()
endif()

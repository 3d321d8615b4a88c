# Command-line tools. Each area appends its tools in src/tools/<area>.cmake.
foreach(area dataset icgm sim slam map slam_map)
  if(EXISTS ${PROJECT_SOURCE_DIR}/src/tools/${area}.cmake)
    include(${PROJECT_SOURCE_DIR}/src/tools/${area}.cmake)
  endif()
endforeach()

# RGB-D sensor access through OpenNI2: device clock mapping, depth-colour pairing, the OpenNI2
# camera, and the project's virtual OpenNI2 device driver (a TUM folder or a simulated scenario
# served as a Kinect).
#
# OpenNI2 loads its drivers from "OpenNI2/Drivers/lib*.so.0" beside the libOpenNI2 it was
# loaded from (Debian's build reads its OpenNI.ini only from /etc/openni2, whose Repository
# entry is the same relative path by default). The build therefore makes a folder with a link
# to the system libOpenNI2 and, beside it, OpenNI2/Drivers holding links to the system drivers
# (PS1080, OniFile, ... whatever is installed) and the virtual driver. Everything linking
# icgm_openni2 finds libOpenNI2 there (the folder is on its run path) and so sees all of them.
find_path(ICGM_OPENNI2_INCLUDE_DIR OpenNI.h PATH_SUFFIXES openni2)
find_library(ICGM_OPENNI2_SYSTEM_LIBRARY NAMES OpenNI2)
if(NOT ICGM_OPENNI2_INCLUDE_DIR OR NOT ICGM_OPENNI2_SYSTEM_LIBRARY)
  message(STATUS "OpenNI2 not found (libopenni2-dev): the sensor module is not built")
  return()
endif()
get_filename_component(ICGM_OPENNI2_SYSTEM_REAL ${ICGM_OPENNI2_SYSTEM_LIBRARY} REALPATH)
get_filename_component(ICGM_OPENNI2_SYSTEM_DIR ${ICGM_OPENNI2_SYSTEM_REAL} DIRECTORY)
if(CATKIN_DEVEL_PREFIX AND NOT ICGM_CORE_ONLY)
  set(ICGM_OPENNI2_DIR ${CATKIN_DEVEL_PREFIX}/lib/icgm_openni2)
else()
  set(ICGM_OPENNI2_DIR ${CMAKE_BINARY_DIR}/icgm_openni2)
endif()
set(ICGM_OPENNI2_DRIVER_DIR ${ICGM_OPENNI2_DIR}/OpenNI2/Drivers)
file(MAKE_DIRECTORY ${ICGM_OPENNI2_DRIVER_DIR})
file(CREATE_LINK ${ICGM_OPENNI2_SYSTEM_REAL} ${ICGM_OPENNI2_DIR}/libOpenNI2.so.0 SYMBOLIC)
file(GLOB ICGM_OPENNI2_SYSTEM_DRIVERS ${ICGM_OPENNI2_SYSTEM_DIR}/OpenNI2/Drivers/lib*.so.0)
foreach(driver ${ICGM_OPENNI2_SYSTEM_DRIVERS})
  get_filename_component(name ${driver} NAME)
  file(CREATE_LINK ${driver} ${ICGM_OPENNI2_DRIVER_DIR}/${name} SYMBOLIC)
endforeach()

add_library(icgm_openni2 SHARED IMPORTED GLOBAL)
set_target_properties(icgm_openni2 PROPERTIES
  IMPORTED_LOCATION ${ICGM_OPENNI2_DIR}/libOpenNI2.so.0
  INTERFACE_INCLUDE_DIRECTORIES ${ICGM_OPENNI2_INCLUDE_DIR})

icgm_core_module(NAME sensor
  SOURCES
    src/core/sensor/depth_registration.cpp
    src/core/sensor/device_clock.cpp
    src/core/sensor/fakenect_dump.cpp
    src/core/sensor/frame_pairer.cpp
    src/core/sensor/kinect_disparity.cpp
    src/core/sensor/openni_camera.cpp
    src/core/sensor/rgbd_calibration.cpp
    src/core/sensor/virtual_device_uri.cpp
    src/core/sensor/virtual_frame_source.cpp
    src/core/sensor/tum_frame_source.cpp
    src/core/sensor/sim_frame_source.cpp
    src/core/sensor/robot_options.cpp
  DEPS icgm_core_common icgm_core_dataset icgm_core_sim icgm_openni2 opencv_core opencv_imgproc pthread)

# The registration's per-row projection loop vectorises only when float comparisons may be
# reordered without regard to floating-point exception flags (results are unchanged).
set_source_files_properties(src/core/sensor/depth_registration.cpp PROPERTIES
  COMPILE_OPTIONS -fno-trapping-math)

# The virtual driver: lib icgm_virtual_device.so.0 in the drivers folder (OpenNI2 loads only
# files named lib*.so.0 there).
add_library(icgm_virtual_device SHARED src/core/sensor/virtual_driver.cpp)
target_include_directories(icgm_virtual_device PRIVATE ${ICGM_OPENNI2_INCLUDE_DIR})
target_link_libraries(icgm_virtual_device PRIVATE icgm_core_sensor)
set_target_properties(icgm_virtual_device PROPERTIES
  LIBRARY_OUTPUT_DIRECTORY ${ICGM_OPENNI2_DRIVER_DIR}
  OUTPUT_NAME icgm_virtual_device SUFFIX ".so.0")

# The Kinect v1 driver on libfreenect (optional: without libfreenect-dev the build goes on
# without it and says so): lib icgm_freenect_device.so.0 in the drivers folder.
find_path(ICGM_FREENECT_INCLUDE_DIR libfreenect.h PATH_SUFFIXES libfreenect)
find_library(ICGM_FREENECT_LIBRARY NAMES freenect)
if(ICGM_FREENECT_INCLUDE_DIR AND ICGM_FREENECT_LIBRARY)
  add_library(icgm_freenect_device SHARED src/core/sensor/freenect_driver.cpp)
  target_include_directories(icgm_freenect_device PRIVATE ${ICGM_OPENNI2_INCLUDE_DIR}
                             ${ICGM_FREENECT_INCLUDE_DIR})
  target_link_libraries(icgm_freenect_device PRIVATE icgm_core_sensor ${ICGM_FREENECT_LIBRARY} dl)
  set_target_properties(icgm_freenect_device PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${ICGM_OPENNI2_DRIVER_DIR}
    OUTPUT_NAME icgm_freenect_device SUFFIX ".so.0")
  get_filename_component(ICGM_FREENECT_LIBRARY_DIR ${ICGM_FREENECT_LIBRARY} DIRECTORY)
  message(STATUS "libfreenect found: building the Kinect v1 OpenNI2 driver (icgm_freenect_device)")
else()
  message(STATUS "libfreenect not found (libfreenect-dev): the Kinect v1 OpenNI2 driver "
                 "(icgm_freenect_device) is not built")
endif()

icgm_core_test(NAME sensor
  SOURCES
    test/core/sensor/depth_registration_test.cpp
    test/core/sensor/device_clock_test.cpp
    test/core/sensor/fakenect_dump_test.cpp
    test/core/sensor/frame_pairer_test.cpp
    test/core/sensor/kinect_disparity_test.cpp
    test/core/sensor/virtual_device_uri_test.cpp
    test/core/sensor/virtual_device_test.cpp
    test/core/sensor/rgbd_calibration_test.cpp
    test/core/sensor/robot_options_test.cpp
  DEPS icgm_core_sensor)
if(TARGET icgm_sensor_test)
  add_dependencies(icgm_sensor_test icgm_virtual_device)
endif()

# The Kinect v1 driver on a fakenect dump (fakenect: libfreenect's replaying library, which the
# test puts first on its library path by restarting itself). Skips without fakenect.
if(TARGET icgm_freenect_device)
  icgm_core_test(NAME freenect
    SOURCES test/core/sensor/freenect_driver_test.cpp
    DEPS icgm_core_sensor)
  if(TARGET icgm_freenect_test)
    add_dependencies(icgm_freenect_test icgm_freenect_device icgm_virtual_device)
    target_compile_definitions(icgm_freenect_test PRIVATE
      ICGM_FAKENECT_DIR="${ICGM_FREENECT_LIBRARY_DIR}/fakenect")
  endif()
endif()

# The same folder in the install space (lib/icgm_slam/icgm_openni2): links to the system
# libOpenNI2 and drivers, the virtual driver, and an OpenNI.ini whose driver repository is the
# installed folder (read by OpenNI2 builds that take OpenNI.ini from beside the library; Debian's
# reads /etc/openni2/OpenNI.ini, whose default repository is the same folder relative to the
# library). Installed programs find the link first on their run path. Component icgm_openni2
# (launch_scripts/check_openni2_install.sh installs and checks it on its own).
if(CATKIN_DEVEL_PREFIX AND NOT ICGM_CORE_ONLY)
  set(ICGM_OPENNI2_INSTALL_DIR ${CMAKE_INSTALL_PREFIX}/${ICGM_LIB_DIR}/icgm_openni2)
  list(APPEND CMAKE_INSTALL_RPATH ${ICGM_OPENNI2_INSTALL_DIR})
  set(ICGM_OPENNI2_REPOSITORY ${ICGM_OPENNI2_DRIVER_DIR})
  configure_file(${PROJECT_SOURCE_DIR}/src/core/sensor/OpenNI.ini.in
                 ${ICGM_OPENNI2_DIR}/OpenNI.ini @ONLY)
  set(ICGM_OPENNI2_REPOSITORY ${ICGM_OPENNI2_INSTALL_DIR}/OpenNI2/Drivers)
  configure_file(${PROJECT_SOURCE_DIR}/src/core/sensor/OpenNI.ini.in
                 ${CMAKE_CURRENT_BINARY_DIR}/icgm_openni2_install/OpenNI.ini @ONLY)
  install(TARGETS icgm_virtual_device
          LIBRARY DESTINATION ${ICGM_LIB_DIR}/icgm_openni2/OpenNI2/Drivers COMPONENT icgm_openni2)
  if(TARGET icgm_freenect_device)
    install(TARGETS icgm_freenect_device
            LIBRARY DESTINATION ${ICGM_LIB_DIR}/icgm_openni2/OpenNI2/Drivers COMPONENT icgm_openni2)
  endif()
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/icgm_openni2_install/OpenNI.ini
          DESTINATION ${ICGM_LIB_DIR}/icgm_openni2 COMPONENT icgm_openni2)
  install(CODE "
    set(dir \"\$ENV{DESTDIR}${ICGM_OPENNI2_INSTALL_DIR}\")
    file(MAKE_DIRECTORY \"\${dir}/OpenNI2/Drivers\")
    file(CREATE_LINK \"${ICGM_OPENNI2_SYSTEM_REAL}\" \"\${dir}/libOpenNI2.so.0\" SYMBOLIC)
    foreach(driver ${ICGM_OPENNI2_SYSTEM_DRIVERS})
      get_filename_component(name \${driver} NAME)
      file(CREATE_LINK \${driver} \"\${dir}/OpenNI2/Drivers/\${name}\" SYMBOLIC)
    endforeach()
    message(STATUS \"Installing: \${dir} (links to the system OpenNI2 and its drivers)\")
  " COMPONENT icgm_openni2)
endif()

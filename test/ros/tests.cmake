# rostests: simulator bags generated at build time (never committed) replayed through the nodelets.
set(ICGM_TEST_DATA ${CATKIN_DEVEL_PREFIX}/share/icgm_slam/test_data)
set(ICGM_TEST_BAG_CROWDED ${ICGM_TEST_DATA}/crowded_short.bag)
add_custom_command(OUTPUT ${ICGM_TEST_BAG_CROWDED}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND icgm_sim --config ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml --frames 70
          --out ${ICGM_TEST_BAG_CROWDED}
  DEPENDS icgm_sim ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml
  COMMENT "Rendering the crowded test bag")
set(ICGM_TEST_BAG_LOOP ${ICGM_TEST_DATA}/small_loop.bag)
add_custom_command(OUTPUT ${ICGM_TEST_BAG_LOOP}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND icgm_sim --config ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml
          --out ${ICGM_TEST_BAG_LOOP}
  DEPENDS icgm_sim ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml
  COMMENT "Rendering the loop test bag")
# The whole crowded scenario (as rosbags/crowded.bag of the demo: 300 frames, 11.6 m with a
# turn, so the ATE alignment is well posed) for the live-equals-offline comparison.
set(ICGM_TEST_BAG_CROWDED_LIVE ${ICGM_TEST_DATA}/crowded_live.bag)
add_custom_command(OUTPUT ${ICGM_TEST_BAG_CROWDED_LIVE}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND icgm_sim --config ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml
          --out ${ICGM_TEST_BAG_CROWDED_LIVE}
  DEPENDS icgm_sim ${PROJECT_SOURCE_DIR}/config/sim/crowded.yaml
  COMMENT "Rendering the crowded live-vs-offline test bag")
add_custom_target(icgm_test_bags DEPENDS ${ICGM_TEST_BAG_CROWDED} ${ICGM_TEST_BAG_LOOP}
  ${ICGM_TEST_BAG_CROWDED_LIVE})
add_dependencies(tests icgm_test_bags)
# The start of the real TUM fr1/xyz sequence, converted from ../shared/data when it is there.
# (The source dir may be a symlink, whose ".." make would take literally: resolve it first.)
get_filename_component(ICGM_REAL_SOURCE_DIR ${PROJECT_SOURCE_DIR} REALPATH)
get_filename_component(ICGM_TUM_DIR ${ICGM_REAL_SOURCE_DIR}/../shared/data/tum_fr1_xyz REALPATH)
set(ICGM_TEST_BAG_TUM ${ICGM_TEST_DATA}/tum_fr1_xyz_150.bag)
if(EXISTS ${ICGM_TUM_DIR}/rgb.txt)
  add_custom_command(OUTPUT ${ICGM_TEST_BAG_TUM}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
    COMMAND icgm_tum_to_bag ${ICGM_TUM_DIR} --out ${ICGM_TEST_BAG_TUM}
            --camera ${PROJECT_SOURCE_DIR}/config/camera/tum_fr1.yaml --frames 150
    DEPENDS icgm_tum_to_bag ${ICGM_TUM_DIR}/rgb.txt
    COMMENT "Converting the TUM fr1/xyz test bag")
  add_custom_target(icgm_test_bag_tum DEPENDS ${ICGM_TEST_BAG_TUM})
  add_dependencies(tests icgm_test_bag_tum)
endif()

add_library(icgm_rostest_common STATIC EXCLUDE_FROM_ALL test/ros/bag_replayer.cpp
  test/ros/sibling_executable.cpp test/ros/process_cpu.cpp)
icgm_unity(icgm_rostest_common)
target_include_directories(icgm_rostest_common PUBLIC ${PROJECT_SOURCE_DIR}/src ${catkin_INCLUDE_DIRS})
target_link_libraries(icgm_rostest_common icgm_ros_bridge ${catkin_LIBRARIES})

# The gtest nodes of all rostests are one executable (each .test file selects its test case with
# --gtest_filter), compiled in batches: the ROS, rosbag, gtest, Eigen and OpenCV headers are
# parsed once per batch instead of once per test, and one binary is linked instead of sixteen.
# The data and programs the tests use are its dependencies (added with each test below).
add_executable(icgm_rostests EXCLUDE_FROM_ALL
  test/ros/rostest_main.cpp
  test/ros/feature_extraction_rostest.cpp
  test/ros/odometry_rostest.cpp
  test/ros/live_offline_rostest.cpp
  test/ros/camera_only_rostest.cpp
  test/ros/extrinsic_wait_rostest.cpp
  test/ros/rosbag_play_rostest.cpp
  test/ros/map_builder_rostest.cpp
  test/ros/registration_tum_rostest.cpp
  test/ros/mono_odometry_rostest.cpp
  test/ros/navigation_rostest.cpp
  test/ros/navigation_sim_rostest.cpp
  test/ros/sim_scan_rostest.cpp
  test/ros/localization_rostest.cpp
  test/ros/openni2_tum_rostest.cpp
  test/ros/openni2_oni_rostest.cpp
  test/ros/openni2_freenect_rostest.cpp
  test/ros/iws09_rostest.cpp
  test/ros/nodelet_params_rostest.cpp)
icgm_unity(icgm_rostests BATCH 9)
target_include_directories(icgm_rostests PRIVATE ${GTEST_INCLUDE_DIRS})
target_link_libraries(icgm_rostests icgm_rostest_common icgm_core_odometry icgm_core_slam
  icgm_core_eval icgm_core_dataset icgm_core_map icgm_core_map_export icgm_core_nav
  icgm_core_mono icgm_core_sensor icgm_core_sim ${GTEST_LIBRARIES})
add_dependencies(icgm_rostests icgm_test_bags ${PROJECT_NAME}_generate_messages_cpp
  icgm_slam_nodelets icgm_slam_offline)
add_dependencies(tests icgm_rostests)

# icgm_add_rostest(launch_file LANE parallel|alone [ARGS ...]): icgm_rostests run by rostest
# through a .test file with launch arguments. launch_scripts/run_tests.sh runs the `parallel`
# lane two tests at a time: tests whose replay waits for the pipeline (lock step, or a clock held
# while the pipeline lags, or a simulator synchronised with it), which a second test on the CPU
# slows without changing what they see. Tests paced by the wall clock (a bag or a device played
# in real time) run `alone`, one after another. rostest names a result file after the launch
# arguments up to the first '.': a .test file run several ways passes variant:=NAME first.
function(icgm_add_rostest launch_file)
  cmake_parse_arguments(R "" "LANE" "ARGS" ${ARGN})
  if(NOT R_LANE MATCHES "^(parallel|alone)$")
    message(FATAL_ERROR "icgm_add_rostest(${launch_file}): LANE parallel or alone")
  endif()
  add_rostest(${launch_file} ARGS ${R_ARGS} DEPENDENCIES icgm_rostests)
  # The run target's name, as add_rostest (rostest-extras.cmake) makes it.
  if(R_ARGS)
    get_filename_component(name ${launch_file} NAME_WE)
    foreach(arg ${R_ARGS})
      string(REPLACE ":=" "_" arg "${arg}")
      set(name "${name}__${arg}")
    endforeach()
    set(name "${name}.test")
  else()
    set(name ${launch_file})
  endif()
  string(REPLACE "/" "_" name ${name})
  set(target run_tests_${PROJECT_NAME}_rostest_${name})
  if(NOT TARGET ${target})
    message(FATAL_ERROR "icgm_add_rostest(${launch_file}): no target ${target}")
  endif()
  set_property(GLOBAL APPEND PROPERTY ICGM_ROSTESTS_${R_LANE} ${target})
endfunction()

icgm_add_rostest(test/ros/feature_extraction.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

icgm_add_rostest(test/ros/odometry.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

# With the map: the map builder nodelet's map against icgm_slam_offline's map of the same bag
# (the tool next to the test binary). At rate 1.0 without holding the clock (every frame played
# in real time must get its relative pose): alone.
icgm_add_rostest(test/ros/live_offline.test LANE alone
  ARGS bag:=${ICGM_TEST_BAG_CROWDED_LIVE})
# The thesis profile: keyframes carry the robust feature tracker's flags (map_features.source
# tracker), held back one frame by the registration nodelet as by icgm_slam_offline; the
# replay waits for a lagging pipeline (the tracker adds CPU per frame).
icgm_add_rostest(test/ros/live_offline.test LANE parallel
  ARGS variant:=thesis bag:=${ICGM_TEST_BAG_CROWDED_LIVE} profile:=thesis max_lag_frames:=1)
# The same on the first 40 frames, whose last makes a keyframe: held by the registration until
# the map builder switches mode before the save, it must enter the map as offline at the end.
icgm_add_rostest(test/ros/live_offline.test LANE parallel
  ARGS variant:=flush bag:=${ICGM_TEST_BAG_CROWDED_LIVE} profile:=thesis max_lag_frames:=1
       max_frames:=40 flush_by_mode_switch:=true)

# The same comparison on the real hand-held crowd (Bonn excerpt, first 150 frames, with lens
# distortion) in the crowd profile without wheels; the replay waits for a lagging pipeline.
get_filename_component(ICGM_BONN_DIR ${ICGM_REAL_SOURCE_DIR}/../shared/data/bonn_crowd_excerpt
  REALPATH)
set(ICGM_TEST_BAG_BONN ${ICGM_TEST_DATA}/bonn_crowd_150.bag)
if(EXISTS ${ICGM_BONN_DIR}/rgb.txt)
  add_custom_command(OUTPUT ${ICGM_TEST_BAG_BONN}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
    COMMAND icgm_tum_to_bag ${ICGM_BONN_DIR} --out ${ICGM_TEST_BAG_BONN}
            --camera ${PROJECT_SOURCE_DIR}/config/camera/bonn_xtion.yaml --frames 150
    DEPENDS icgm_tum_to_bag ${ICGM_BONN_DIR}/rgb.txt
            ${PROJECT_SOURCE_DIR}/config/camera/bonn_xtion.yaml
    COMMENT "Converting the Bonn crowd test bag")
  add_custom_target(icgm_test_bag_bonn DEPENDS ${ICGM_TEST_BAG_BONN})
  add_dependencies(tests icgm_test_bag_bonn)
  add_dependencies(icgm_rostests icgm_test_bag_bonn)
  icgm_add_rostest(test/ros/live_offline.test LANE parallel
    ARGS variant:=bonn bag:=${ICGM_TEST_BAG_BONN} camera_only:=true max_lag_frames:=1
         odometry_config:=odometry_handheld_crowd.yaml)
else()
  message(WARNING "${ICGM_BONN_DIR} missing: the live = offline rostest on the real crowd is "
                  "not registered (SKIPPED)")
endif()

icgm_add_rostest(test/ros/camera_only.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

icgm_add_rostest(test/ros/extrinsic_wait.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

# `rosbag play` in real time: alone.
icgm_add_rostest(test/ros/rosbag_play.test LANE alone
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

icgm_add_rostest(test/ros/map_builder.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_LOOP})

if(EXISTS ${ICGM_TUM_DIR}/rgb.txt)
  add_dependencies(icgm_rostests icgm_test_bag_tum icgm_mono_vo)
  icgm_add_rostest(test/ros/registration_tum.test LANE parallel
    ARGS bag:=${ICGM_TEST_BAG_TUM})
  # Live = offline with the thesis profile's map features on the real camera (hand-held, no
  # wheels; colour and depth stamped apart, so the last frame stays unmatched live).
  icgm_add_rostest(test/ros/live_offline.test LANE parallel
    ARGS variant:=tum bag:=${ICGM_TEST_BAG_TUM} profile:=thesis camera_only:=true
         max_lag_frames:=1)
  # The monocular odometry nodelet against icgm_mono_vo --bag (next to the test binary) on the
  # same bag; the replay stays a bounded number of images ahead of the nodelet; 5 images are
  # also sent at half size and must be refused (the poses of the others unchanged).
  icgm_add_rostest(test/ros/mono_odometry.test LANE parallel
    ARGS bag:=${ICGM_TEST_BAG_TUM} refused_images:=5)
  # ... and on the crowded robot with its wheels (metric scale; measured Sim(3) ATE 0.066 m).
  icgm_add_rostest(test/ros/mono_odometry.test LANE parallel
    ARGS variant:=wheels bag:=${ICGM_TEST_BAG_CROWDED_LIVE} wheels:=true max_ate_m:=0.15)
endif()

# A hybrid map of the simulated loop, built offline, and a file that is not a map.
set(ICGM_TEST_MAP_LOOP ${ICGM_TEST_DATA}/small_loop.db)
set(ICGM_TEST_NOT_A_MAP ${ICGM_TEST_DATA}/not_a_map.db)
add_custom_command(OUTPUT ${ICGM_TEST_MAP_LOOP}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND icgm_slam_offline --sim ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml
          --trajectory ${ICGM_TEST_DATA}/small_loop_map_trajectory.txt --map ${ICGM_TEST_MAP_LOOP}
  DEPENDS icgm_slam_offline ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml
  COMMENT "Building the loop test map")
add_custom_command(OUTPUT ${ICGM_TEST_NOT_A_MAP}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${ICGM_TEST_DATA}
  COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml
          ${ICGM_TEST_NOT_A_MAP}
  DEPENDS ${PROJECT_SOURCE_DIR}/config/sim/small_loop.yaml)
add_custom_target(icgm_test_maps DEPENDS ${ICGM_TEST_MAP_LOOP} ${ICGM_TEST_NOT_A_MAP})

add_dependencies(icgm_rostests icgm_test_maps)
icgm_add_rostest(test/ros/navigation.test LANE parallel
  ARGS map:=${ICGM_TEST_MAP_LOOP} not_a_map:=${ICGM_TEST_NOT_A_MAP})

# Closed loop: the simulator nodelet in the loop's world, localization on its learned map,
# navigation to goals (ground truth from the simulator). The simulator waits for the pipeline,
# but the test gives the robot wall-clock seconds to stop after a cancel: alone.
icgm_add_rostest(test/ros/navigation_sim.test LANE alone
  ARGS map:=${ICGM_TEST_MAP_LOOP})

# Misspelt private parameters of nodelets loaded into a manager are warned about.
icgm_add_rostest(test/ros/nodelet_params.test LANE parallel)

# The simulator nodelet's planar scanner against the same world simulated in the test.
icgm_add_rostest(test/ros/sim_scan.test LANE parallel)

icgm_add_rostest(test/ros/localization.test LANE parallel
  ARGS bag:=${ICGM_TEST_BAG_LOOP} map:=${ICGM_TEST_MAP_LOOP})

# The OpenNI2 driver nodelet on the virtual device playing TUM fr1/xyz, through the pipeline,
# against icgm_slam_offline on the same frames. The device plays in real time: alone.
if(TARGET icgm_virtual_device)
  add_dependencies(icgm_rostests icgm_virtual_device)
endif()
if(EXISTS ${ICGM_TUM_DIR}/rgb.txt AND TARGET icgm_virtual_device)
  icgm_add_rostest(test/ros/openni2_tum.test LANE alone
    ARGS tum_dir:=${ICGM_TUM_DIR}
         offline_tool:=${CATKIN_DEVEL_PREFIX}/lib/icgm_slam/icgm_slam_offline)
endif()

# An .oni recording of the virtual device played back through the driver nodelet (OpenNI's file
# driver), as recorded and registered in software.
if(TARGET icgm_virtual_device)
  icgm_add_rostest(test/ros/openni2_oni.test LANE alone)
endif()

# The Kinect v1 driver through the driver nodelet on a fakenect dump of a simulated scenario
# (written at build time), when the driver is built and libfreenect's fakenect is installed.
if(TARGET icgm_freenect_device AND EXISTS ${ICGM_FREENECT_LIBRARY_DIR}/fakenect)
  set(ICGM_TEST_FAKENECT_DUMP ${ICGM_TEST_DATA}/fakenect_static_short)
  add_custom_command(OUTPUT ${ICGM_TEST_FAKENECT_DUMP}/INDEX.txt
    COMMAND icgm_fakenect_dump --out ${ICGM_TEST_FAKENECT_DUMP} --frames 20
            --source icgm-virtual://sim?scenario=${PROJECT_SOURCE_DIR}/config/sim/static_short.yaml
    DEPENDS icgm_fakenect_dump ${PROJECT_SOURCE_DIR}/config/sim/static_short.yaml
    COMMENT "Writing the fakenect test dump" VERBATIM)
  add_custom_target(icgm_test_fakenect_dump DEPENDS ${ICGM_TEST_FAKENECT_DUMP}/INDEX.txt)
  add_dependencies(icgm_rostests icgm_freenect_device icgm_test_fakenect_dump)
  icgm_add_rostest(test/ros/openni2_freenect.test LANE alone
    ARGS dump:=${ICGM_TEST_FAKENECT_DUMP} fakenect_dir:=${ICGM_FREENECT_LIBRARY_DIR}/fakenect)
endif()

# The iWs09 robot: iws09.launch on the virtual device (tf base_link -> camera, odometry).
if(EXISTS ${ICGM_TUM_DIR}/rgb.txt AND TARGET icgm_virtual_device)
  icgm_add_rostest(test/ros/iws09.test LANE alone
    ARGS tum_dir:=${ICGM_TUM_DIR})
endif()

# The two lanes for run_tests.sh (make icgm_run_rostests_parallel -j2, then
# icgm_run_rostests_alone -j1); run_tests_icgm_slam_rostest still runs every rostest.
foreach(lane parallel alone)
  get_property(lane_targets GLOBAL PROPERTY ICGM_ROSTESTS_${lane})
  add_custom_target(icgm_run_rostests_${lane})
  if(lane_targets)
    add_dependencies(icgm_run_rostests_${lane} ${lane_targets})
  endif()
endforeach()

# Every launch file passes roslaunch's check (arguments, includes, packages, node types).
find_package(roslaunch REQUIRED)
foreach(launch icgm_slam.launch iws09.launch record.launch mono_odometry.launch)
  roslaunch_add_file_check(launch_scripts/${launch})
endforeach()
roslaunch_add_file_check(launch_scripts/replay_bag.launch bag:=/tmp/icgm_check.bag)
roslaunch_add_file_check(launch_scripts/navigation_sim.launch map:=/tmp/icgm_check.db)

# The robot description: check_urdf, and the camera mount equals config/robot/iws09.yaml.
find_package(urdf REQUIRED)
catkin_add_gtest(icgm_robot_description_test test/ros/robot_description_test.cpp
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
if(TARGET icgm_robot_description_test)
  target_include_directories(icgm_robot_description_test PRIVATE ${urdf_INCLUDE_DIRS})
  target_link_libraries(icgm_robot_description_test icgm_core_sensor ${urdf_LIBRARIES} GTest::gtest_main)
  target_compile_definitions(icgm_robot_description_test PRIVATE ICGM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()

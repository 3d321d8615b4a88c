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

add_library(icgm_rostest_common STATIC EXCLUDE_FROM_ALL test/ros/bag_replayer.cpp)
target_include_directories(icgm_rostest_common PUBLIC ${PROJECT_SOURCE_DIR}/src ${catkin_INCLUDE_DIRS})
target_link_libraries(icgm_rostest_common icgm_ros_bridge ${catkin_LIBRARIES})

# icgm_add_rostest(target launch_file SOURCES ... ARGS ...): a gtest node run by rostest with
# launch arguments (add_rostest_gtest cannot pass ARGS).
function(icgm_add_rostest target launch_file)
  cmake_parse_arguments(R "" "" "SOURCES;ARGS" ${ARGN})
  add_executable(${target} EXCLUDE_FROM_ALL ${R_SOURCES})
  target_link_libraries(${target} icgm_rostest_common ${GTEST_LIBRARIES})
  target_include_directories(${target} PRIVATE ${GTEST_INCLUDE_DIRS})
  add_dependencies(${target} icgm_test_bags ${PROJECT_NAME}_generate_messages_cpp icgm_slam_nodelets)
  add_dependencies(tests ${target})
  add_rostest(${launch_file} ARGS ${R_ARGS} DEPENDENCIES ${target})
endfunction()

icgm_add_rostest(icgm_feature_extraction_rostest test/ros/feature_extraction.test
  SOURCES test/ros/feature_extraction_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})

icgm_add_rostest(icgm_odometry_rostest test/ros/odometry.test
  SOURCES test/ros/odometry_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})
target_link_libraries(icgm_odometry_rostest icgm_core_dataset)

# With the map: the map builder nodelet's map against icgm_slam_offline's map of the same bag
# (the tool next to the test binary).
icgm_add_rostest(icgm_live_offline_rostest test/ros/live_offline.test
  SOURCES test/ros/live_offline_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED_LIVE})
target_link_libraries(icgm_live_offline_rostest icgm_core_odometry icgm_core_slam icgm_core_eval
  icgm_core_dataset icgm_core_map)
add_dependencies(icgm_live_offline_rostest icgm_slam_offline)
# The thesis profile: keyframes carry the robust feature tracker's flags (map_features.source
# tracker), held back one frame by the registration nodelet as by icgm_slam_offline; the
# replay waits for a lagging pipeline (the tracker adds CPU per frame).
add_rostest(test/ros/live_offline.test
  ARGS bag:=${ICGM_TEST_BAG_CROWDED_LIVE} profile:=thesis max_lag_frames:=1
  DEPENDENCIES icgm_live_offline_rostest)
# The same on the first 40 frames, whose last makes a keyframe: held by the registration until
# the map builder switches mode before the save, it must enter the map as offline at the end.
add_rostest(test/ros/live_offline.test
  ARGS bag:=${ICGM_TEST_BAG_CROWDED_LIVE} profile:=thesis max_lag_frames:=1 max_frames:=40
       flush_by_mode_switch:=true
  DEPENDENCIES icgm_live_offline_rostest)

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
  add_rostest(test/ros/live_offline.test
    ARGS bag:=${ICGM_TEST_BAG_BONN} camera_only:=true max_lag_frames:=1
         odometry_config:=${PROJECT_SOURCE_DIR}/config/odometry_handheld_crowd.yaml
    DEPENDENCIES icgm_live_offline_rostest icgm_test_bag_bonn)
else()
  message(WARNING "${ICGM_BONN_DIR} missing: the live = offline rostest on the real crowd is "
                  "not registered (SKIPPED)")
endif()

icgm_add_rostest(icgm_camera_only_rostest test/ros/camera_only.test
  SOURCES test/ros/camera_only_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})
target_link_libraries(icgm_camera_only_rostest icgm_core_dataset)

icgm_add_rostest(icgm_extrinsic_wait_rostest test/ros/extrinsic_wait.test
  SOURCES test/ros/extrinsic_wait_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})
target_link_libraries(icgm_extrinsic_wait_rostest icgm_core_dataset)

icgm_add_rostest(icgm_rosbag_play_rostest test/ros/rosbag_play.test
  SOURCES test/ros/rosbag_play_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_CROWDED})
target_link_libraries(icgm_rosbag_play_rostest icgm_core_dataset)

icgm_add_rostest(icgm_map_builder_rostest test/ros/map_builder.test
  SOURCES test/ros/map_builder_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_LOOP})
target_link_libraries(icgm_map_builder_rostest icgm_core_map_export icgm_core_map icgm_core_dataset)

if(EXISTS ${ICGM_TUM_DIR}/rgb.txt)
  icgm_add_rostest(icgm_registration_tum_rostest test/ros/registration_tum.test
    SOURCES test/ros/registration_tum_rostest.cpp
    ARGS bag:=${ICGM_TEST_BAG_TUM})
  target_link_libraries(icgm_registration_tum_rostest icgm_core_eval icgm_core_dataset)
  # Live = offline with the thesis profile's map features on the real camera (hand-held, no
  # wheels; colour and depth stamped apart, so the last frame stays unmatched live).
  add_rostest(test/ros/live_offline.test
    ARGS bag:=${ICGM_TEST_BAG_TUM} profile:=thesis camera_only:=true max_lag_frames:=1
    DEPENDENCIES icgm_live_offline_rostest icgm_test_bag_tum)
  # The monocular odometry nodelet against icgm_mono_vo --bag on the same bag.
  icgm_add_rostest(icgm_mono_odometry_rostest test/ros/mono_odometry.test
    SOURCES test/ros/mono_odometry_rostest.cpp
    ARGS bag:=${ICGM_TEST_BAG_TUM} mono_vo:=${CATKIN_DEVEL_PREFIX}/lib/icgm_slam/icgm_mono_vo)
  target_link_libraries(icgm_mono_odometry_rostest icgm_core_mono icgm_core_dataset)
  add_dependencies(icgm_mono_odometry_rostest icgm_mono_vo icgm_test_bag_tum)
  # ... and on the crowded robot with its wheels (metric scale; measured Sim(3) ATE 0.066 m).
  add_rostest(test/ros/mono_odometry.test
    ARGS bag:=${ICGM_TEST_BAG_CROWDED_LIVE} wheels:=true max_ate_m:=0.15
         mono_vo:=${CATKIN_DEVEL_PREFIX}/lib/icgm_slam/icgm_mono_vo
    DEPENDENCIES icgm_mono_odometry_rostest)
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

icgm_add_rostest(icgm_navigation_rostest test/ros/navigation.test
  SOURCES test/ros/navigation_rostest.cpp
  ARGS map:=${ICGM_TEST_MAP_LOOP} not_a_map:=${ICGM_TEST_NOT_A_MAP})
target_link_libraries(icgm_navigation_rostest icgm_core_map icgm_core_nav)
add_dependencies(icgm_navigation_rostest icgm_test_maps)

# Closed loop: the simulator nodelet in the loop's world, localization on its learned map,
# navigation to goals (ground truth from the simulator).
icgm_add_rostest(icgm_navigation_sim_rostest test/ros/navigation_sim.test
  SOURCES test/ros/navigation_sim_rostest.cpp
  ARGS map:=${ICGM_TEST_MAP_LOOP})
target_link_libraries(icgm_navigation_sim_rostest icgm_core_map)
add_dependencies(icgm_navigation_sim_rostest icgm_test_maps)

icgm_add_rostest(icgm_localization_rostest test/ros/localization.test
  SOURCES test/ros/localization_rostest.cpp
  ARGS bag:=${ICGM_TEST_BAG_LOOP} map:=${ICGM_TEST_MAP_LOOP})
target_link_libraries(icgm_localization_rostest icgm_core_map icgm_core_map_export)
add_dependencies(icgm_localization_rostest icgm_test_maps)

# The OpenNI2 driver nodelet on the virtual device playing TUM fr1/xyz, through the pipeline,
# against icgm_slam_offline on the same frames.
if(EXISTS ${ICGM_TUM_DIR}/rgb.txt AND TARGET icgm_virtual_device)
  icgm_add_rostest(icgm_openni2_tum_rostest test/ros/openni2_tum.test
    SOURCES test/ros/openni2_tum_rostest.cpp
    ARGS tum_dir:=${ICGM_TUM_DIR}
         offline_tool:=${CATKIN_DEVEL_PREFIX}/lib/icgm_slam/icgm_slam_offline)
  target_link_libraries(icgm_openni2_tum_rostest icgm_core_eval icgm_core_dataset)
  add_dependencies(icgm_openni2_tum_rostest icgm_slam_offline icgm_virtual_device)
endif()

# An .oni recording of the virtual device played back through the driver nodelet (OpenNI's file
# driver), as recorded and registered in software.
if(TARGET icgm_virtual_device)
  icgm_add_rostest(icgm_openni2_oni_rostest test/ros/openni2_oni.test
    SOURCES test/ros/openni2_oni_rostest.cpp)
  target_link_libraries(icgm_openni2_oni_rostest icgm_core_sensor icgm_core_sim icgm_core_dataset)
  add_dependencies(icgm_openni2_oni_rostest icgm_virtual_device)
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
  icgm_add_rostest(icgm_openni2_freenect_rostest test/ros/openni2_freenect.test
    SOURCES test/ros/openni2_freenect_rostest.cpp
    ARGS dump:=${ICGM_TEST_FAKENECT_DUMP} fakenect_dir:=${ICGM_FREENECT_LIBRARY_DIR}/fakenect)
  target_link_libraries(icgm_openni2_freenect_rostest icgm_core_sensor icgm_core_dataset)
  add_dependencies(icgm_openni2_freenect_rostest icgm_freenect_device icgm_test_fakenect_dump)
endif()

# The iWs09 robot: iws09.launch on the virtual device (tf base_link -> camera, odometry).
if(EXISTS ${ICGM_TUM_DIR}/rgb.txt AND TARGET icgm_virtual_device)
  icgm_add_rostest(icgm_iws09_rostest test/ros/iws09.test
    SOURCES test/ros/iws09_rostest.cpp
    ARGS tum_dir:=${ICGM_TUM_DIR})
  target_link_libraries(icgm_iws09_rostest icgm_core_sensor)
  add_dependencies(icgm_iws09_rostest icgm_virtual_device)
endif()

# Every launch file passes roslaunch's check (arguments, includes, packages, node types).
find_package(roslaunch REQUIRED)
foreach(launch icgm_slam.launch iws09.launch record.launch mono_odometry.launch)
  roslaunch_add_file_check(launch_scripts/${launch})
endforeach()
roslaunch_add_file_check(launch_scripts/replay_bag.launch bag:=/tmp/icgm_check.bag)

# The robot description: check_urdf, and the camera mount equals config/robot/iws09.yaml.
find_package(urdf REQUIRED)
catkin_add_gtest(icgm_robot_description_test test/ros/robot_description_test.cpp
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
if(TARGET icgm_robot_description_test)
  target_include_directories(icgm_robot_description_test PRIVATE ${urdf_INCLUDE_DIRS})
  target_link_libraries(icgm_robot_description_test icgm_core_sensor ${urdf_LIBRARIES} GTest::gtest_main)
  target_compile_definitions(icgm_robot_description_test PRIVATE ICGM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()

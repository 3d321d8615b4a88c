# PCL: only the components used (common, filters); the full package drags VTK into the link line.
find_package(PCL 1.13 REQUIRED COMPONENTS common filters)
# OMPL: its config adds /usr/include as an include directory and links ODE; take the library
# and its header directory only.
find_path(ICGM_OMPL_INCLUDE_DIR ompl/config.h PATH_SUFFIXES ompl-1.5 REQUIRED)
find_library(ICGM_OMPL_LIBRARY NAMES ompl REQUIRED)

icgm_core_module(NAME nav
  SOURCES
    src/core/nav/graph_planner.cpp
    src/core/nav/loop_follower.cpp
    src/core/nav/obstacle_grid.cpp
    src/core/nav/local_planner.cpp
    src/core/nav/dubins_rejoin.cpp
    src/core/nav/tracking_controller.cpp
    src/core/nav/obstacle_tracker.cpp
    src/core/nav/crowd_guard.cpp
    src/core/nav/navigation_options.cpp
    src/core/nav/navigator.cpp
    src/core/nav/goal_session.cpp
    src/core/nav/navigation_phase.cpp
  DEPS icgm_core_map icgm_core_common ${PCL_COMMON_LIBRARIES} ${PCL_FILTERS_LIBRARIES}
       ${ICGM_OMPL_LIBRARY} opencv_core opencv_imgproc)
target_include_directories(icgm_core_nav SYSTEM PUBLIC ${PCL_INCLUDE_DIRS} ${ICGM_OMPL_INCLUDE_DIR})
target_compile_definitions(icgm_core_nav PUBLIC ${PCL_DEFINITIONS})

icgm_core_test(NAME nav
  SOURCES
    test/core/nav/graph_planner_test.cpp
    test/core/nav/loop_follower_test.cpp
    test/core/nav/obstacle_grid_test.cpp
    test/core/nav/local_planner_test.cpp
    test/core/nav/dubins_rejoin_test.cpp
    test/core/nav/tracking_controller_test.cpp
    test/core/nav/obstacle_tracker_test.cpp
    test/core/nav/crowd_guard_test.cpp
    test/core/nav/navigator_test.cpp
    test/core/nav/goal_session_test.cpp
    test/core/nav/navigation_phase_test.cpp
  DEPS icgm_core_nav)

# Closed loop with the simulator: the Navigator drives the ClosedLoopSimulator's robot.
icgm_core_test(NAME nav_closed_loop
  SOURCES test/core/nav/closed_loop_drive_test.cpp
  DEPS icgm_core_nav icgm_core_sim)

icgm_core_module(NAME nav
  SOURCES
    src/core/nav/graph_planner.cpp
    src/core/nav/loop_follower.cpp
  DEPS icgm_core_map)

icgm_core_test(NAME nav
  SOURCES
    test/core/nav/graph_planner_test.cpp
    test/core/nav/loop_follower_test.cpp
  DEPS icgm_core_nav)

icgm_core_module(NAME geometry
  SOURCES
    src/core/geometry/absolute_orientation.cpp
  DEPS icgm_core_common Eigen3::Eigen)

icgm_core_test(NAME geometry
  SOURCES
    test/core/geometry/absolute_orientation_test.cpp
  DEPS icgm_core_geometry)

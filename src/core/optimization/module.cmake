icgm_core_module(NAME optimization
  SOURCES
    src/core/optimization/bundle_adjustment.cpp
    src/core/optimization/pixel_observation_cost.cpp
  DEPS icgm_core_common Eigen3::Eigen)

# Without Ceres the solvers are compiled out and report "built without Ceres".
if(TARGET Ceres::ceres)
  target_link_libraries(icgm_core_optimization PUBLIC Ceres::ceres)
  target_compile_definitions(icgm_core_optimization PRIVATE ICGM_HAVE_CERES)
endif()

icgm_core_test(NAME optimization
  SOURCES
    test/core/optimization/bundle_adjustment_test.cpp
    test/core/optimization/pixel_observation_cost_test.cpp
  DEPS icgm_core_optimization ${OpenCV_LIBS})

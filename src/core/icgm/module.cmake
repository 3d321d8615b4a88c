icgm_core_module(NAME icgm
  SOURCES
    src/core/icgm/icgm_matcher.cpp
    src/core/icgm/robust_feature_tracker.cpp
  DEPS icgm_core_features icgm_core_common Eigen3::Eigen ${OpenCV_LIBS})

icgm_core_test(NAME icgm
  SOURCES
    test/core/icgm/synthetic_scene.cpp
    test/core/icgm/icgm_matcher_test.cpp
    test/core/icgm/robust_feature_tracker_test.cpp
    test/core/icgm/icgm_worked_example_test.cpp
  DEPS icgm_core_icgm)

icgm_core_module(NAME features
  SOURCES
    src/core/features/feature_extractor.cpp
    src/core/features/descriptor_matcher.cpp
    src/core/features/hamming_knn.cpp
    src/core/features/fast_hessian.cpp
    src/core/features/surf_descriptor.cpp
    src/core/features/surf.cpp
    src/core/features/lens_undistortion.cpp
  DEPS icgm_core_common ${OpenCV_LIBS})

icgm_core_test(NAME features
  SOURCES
    test/core/features/feature_extractor_test.cpp
    test/core/features/descriptor_matcher_test.cpp
    test/core/features/hamming_knn_test.cpp
    test/core/features/surf_test.cpp
    test/core/features/lens_undistortion_test.cpp
    test/core/icgm/synthetic_scene.cpp
  DEPS icgm_core_features)

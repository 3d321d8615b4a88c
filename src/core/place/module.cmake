# Appearance-only place recognition: weighted dictionary queries, minimum-words guard, temporal
# consistency and geometric verification of loop hypotheses.
icgm_core_module(NAME place
  SOURCES
    src/core/place/place_options.cpp
    src/core/place/temporal_consistency.cpp
    src/core/place/geometric_verification.cpp
    src/core/place/place_recognizer.cpp
  DEPS icgm_core_map icgm_core_registration icgm_core_features icgm_core_common ${OpenCV_LIBS})

icgm_core_test(NAME place
  SOURCES
    test/core/place/temporal_consistency_test.cpp
    test/core/place/geometric_verification_test.cpp
    test/core/place/place_recognizer_test.cpp
  DEPS icgm_core_place)

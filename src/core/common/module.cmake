icgm_core_module(NAME common
  SOURCES
    src/core/common/time.cpp
    src/core/common/image_size.cpp
    src/core/common/pose.cpp
    src/core/common/enum_names.cpp
    src/core/common/option_reader.cpp
    src/core/common/progress_bar.cpp
    src/core/common/sample_summary.cpp
    src/core/common/fixed_text.cpp
    src/core/common/planar_scan.cpp
  DEPS Eigen3::Eigen yaml-cpp)

icgm_core_test(NAME common
  SOURCES
    test/core/common/time_test.cpp
    test/core/common/pose_test.cpp
    test/core/common/option_reader_test.cpp
    test/core/common/core_isolation_test.cpp
    test/core/common/sample_summary_test.cpp
  DEPS icgm_core_common)

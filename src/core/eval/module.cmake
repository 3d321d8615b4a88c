icgm_core_module(NAME eval
  SOURCES
    src/core/eval/error_stats.cpp
    src/core/eval/trajectory_evaluation.cpp
    src/core/eval/error_terms.cpp
    src/core/eval/plot_axes.cpp
    src/core/eval/trajectory_plot.cpp
    src/core/eval/place_truth.cpp
    src/core/eval/precision_recall.cpp
    src/core/eval/precision_recall_plot.cpp
    src/core/eval/match_reprojection.cpp
    src/core/eval/keypoint_repeatability.cpp
    src/core/eval/background_depth.cpp
  DEPS icgm_core_dataset icgm_core_geometry icgm_core_common opencv_core opencv_imgproc
       opencv_imgcodecs)

icgm_core_test(NAME eval
  SOURCES
    test/core/eval/error_stats_test.cpp
    test/core/eval/trajectory_evaluation_test.cpp
    test/core/eval/error_terms_test.cpp
    test/core/eval/trajectory_plot_test.cpp
    test/core/eval/place_truth_test.cpp
    test/core/eval/precision_recall_test.cpp
    test/core/eval/match_reprojection_test.cpp
    test/core/eval/keypoint_repeatability_test.cpp
    test/core/eval/background_depth_test.cpp
  DEPS icgm_core_eval)

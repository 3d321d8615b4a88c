icgm_core_module(NAME mono
  SOURCES
    src/core/mono/mono_options.cpp
    src/core/mono/triangulation.cpp
    src/core/mono/ransac_order.cpp
    src/core/mono/two_view.cpp
    src/core/mono/rotation_only.cpp
    src/core/mono/pnp_pose.cpp
    src/core/mono/mono_odometry.cpp
    src/core/mono/mono_evaluation.cpp
    src/core/mono/mono_pose_gaps.cpp
    src/core/mono/mono_input_queue.cpp
  DEPS icgm_core_odometry icgm_core_optimization icgm_core_eval icgm_core_dataset icgm_core_icgm icgm_core_features icgm_core_geometry
       icgm_core_common Eigen3::Eigen ${OpenCV_LIBS})

icgm_core_test(NAME mono
  SOURCES
    test/core/mono/two_view_test.cpp
    test/core/mono/rotation_only_test.cpp
    test/core/mono/pnp_triangulation_test.cpp
    test/core/mono/mono_odometry_test.cpp
    test/core/mono/mono_input_queue_test.cpp
    test/core/mono/mono_evaluation_test.cpp
    test/core/mono/mono_pose_gaps_test.cpp
  DEPS icgm_core_mono icgm_core_sim icgm_core_eval icgm_core_dataset)

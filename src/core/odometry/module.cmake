icgm_core_module(NAME odometry
  SOURCES
    src/core/odometry/wheel_odometry_buffer.cpp
    src/core/odometry/odometry_fusion.cpp
    src/core/odometry/frontend_options.cpp
    src/core/odometry/rgbd_frontend.cpp
    src/core/odometry/vision_step.cpp
    src/core/odometry/fusion_queue.cpp
    src/core/odometry/live_fusion.cpp
    src/core/odometry/velocity_history.cpp
    src/core/odometry/prior_reset.cpp
    src/core/odometry/registration_agreement.cpp
    src/core/odometry/hypothesis_evidence.cpp
    src/core/odometry/pose_window.cpp
    src/core/odometry/local_map.cpp
    src/core/odometry/map_hypothesis.cpp
    src/core/odometry/keyframe_bundle_adjustment.cpp
    src/core/odometry/anchor_keyframes.cpp
    src/core/odometry/residual_trend.cpp
  DEPS icgm_core_optimization icgm_core_registration icgm_core_icgm icgm_core_features icgm_core_common
       Eigen3::Eigen ${OpenCV_LIBS})

icgm_core_test(NAME odometry
  SOURCES
    test/core/odometry/wheel_odometry_buffer_test.cpp
    test/core/odometry/odometry_fusion_test.cpp
    test/core/odometry/rgbd_frontend_test.cpp
    test/core/odometry/crowd_frontend_test.cpp
    test/core/odometry/vision_step_test.cpp
    test/core/odometry/fusion_queue_test.cpp
    test/core/odometry/live_fusion_test.cpp
    test/core/odometry/velocity_history_test.cpp
    test/core/odometry/prior_reset_test.cpp
    test/core/odometry/registration_agreement_test.cpp
    test/core/odometry/hypothesis_evidence_test.cpp
    test/core/odometry/pose_window_test.cpp
    test/core/odometry/local_map_test.cpp
    test/core/odometry/keyframe_bundle_adjustment_test.cpp
    test/core/odometry/anchor_keyframes_test.cpp
    test/core/odometry/residual_trend_test.cpp
  DEPS icgm_core_odometry icgm_core_dataset icgm_core_eval icgm_core_sim)

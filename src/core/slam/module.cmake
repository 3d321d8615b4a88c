icgm_core_module(NAME slam
  SOURCES
    src/core/slam/keyframe_conversion.cpp
    src/core/slam/keyframe_registration.cpp
    src/core/slam/map_feature_tracking.cpp
    src/core/slam/map_refinement.cpp
    src/core/slam/nearest_keyframe_localizer.cpp
    src/core/slam/slam_options.cpp
    src/core/slam/slam_system.cpp
    src/core/slam/slam_runner.cpp
    src/core/slam/wheel_feed.cpp
    src/core/slam/live_map.cpp
    src/core/slam/live_frontend.cpp
    src/core/slam/in_flight_limit.cpp
  DEPS icgm_core_map icgm_core_optimization icgm_core_odometry icgm_core_registration icgm_core_icgm
       icgm_core_features icgm_core_dataset icgm_core_common Eigen3::Eigen ${OpenCV_LIBS})

icgm_core_test(NAME slam
  SOURCES
    test/core/slam/keyframe_conversion_test.cpp
    test/core/slam/keyframe_registration_test.cpp
    test/core/slam/map_feature_tracking_test.cpp
    test/core/slam/map_refinement_test.cpp
    test/core/slam/nearest_keyframe_localizer_test.cpp
    test/core/slam/slam_system_test.cpp
    test/core/slam/live_map_test.cpp
    test/core/slam/bonn_crowd_map_test.cpp
  DEPS icgm_core_slam icgm_core_eval icgm_core_sim)

icgm_core_test(NAME slam_localization
  SOURCES test/core/slam/localization_test.cpp test/core/slam/wheel_feed_test.cpp
          test/core/slam/wheel_paced_queue_test.cpp test/core/slam/live_frontend_test.cpp
          test/core/slam/in_flight_limit_test.cpp
  DEPS icgm_core_slam icgm_core_sim)

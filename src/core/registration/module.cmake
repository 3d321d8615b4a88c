icgm_core_module(NAME registration
  SOURCES
    src/core/registration/depth_points.cpp
    src/core/registration/depth_consistency.cpp
    src/core/registration/dynamic_region_fill.cpp
    src/core/registration/dense_refinement.cpp
    src/core/registration/depth_warp.cpp
    src/core/registration/rolling_shutter.cpp
    src/core/registration/sensor_timing.cpp
    src/core/registration/ransac_horn.cpp
    src/core/registration/pose_refinement.cpp
    src/core/registration/rgbd_registration.cpp
  DEPS icgm_core_geometry icgm_core_common Eigen3::Eigen ${OpenCV_LIBS})

icgm_core_test(NAME registration
  SOURCES
    test/core/registration/depth_points_test.cpp
    test/core/registration/depth_consistency_test.cpp
    test/core/registration/dynamic_region_fill_test.cpp
    test/core/registration/dense_refinement_test.cpp
    test/core/registration/depth_warp_test.cpp
    test/core/registration/rolling_shutter_test.cpp
    test/core/registration/ransac_horn_test.cpp
    test/core/registration/rgbd_registration_test.cpp
  DEPS icgm_core_registration)

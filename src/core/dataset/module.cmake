icgm_core_module(NAME dataset
  SOURCES
    src/core/dataset/text_table.cpp
    src/core/dataset/stamp_association.cpp
    src/core/dataset/trajectory.cpp
    src/core/dataset/depth_image.cpp
    src/core/dataset/depth_buffers.cpp
    src/core/dataset/tum_dataset.cpp
    src/core/dataset/camera_options.cpp
  DEPS icgm_core_common opencv_core opencv_imgcodecs Eigen3::Eigen)

icgm_core_test(NAME dataset
  SOURCES
    test/core/dataset/trajectory_test.cpp
    test/core/dataset/stamp_association_test.cpp
    test/core/dataset/depth_image_test.cpp
    test/core/dataset/depth_buffers_test.cpp
    test/core/dataset/tum_dataset_test.cpp
    test/core/dataset/camera_options_test.cpp
  DEPS icgm_core_dataset opencv_imgproc)

# Every shipped config/**/*.yaml parses and each section is read by its options reader; the
# loaders reject unknown keys and the shipped odometry/icgm/map files equal the code's defaults.
icgm_core_test(NAME config
  SOURCES
    test/core/config/config_files_test.cpp
    test/core/config/config_defaults_test.cpp
    test/core/config/config_choices_test.cpp
  DEPS icgm_core_dataset icgm_core_features icgm_core_icgm icgm_core_registration
       icgm_core_odometry icgm_core_mono icgm_core_map icgm_core_sim icgm_core_slam icgm_core_common icgm_core_nav icgm_core_sensor icgm_core_place)

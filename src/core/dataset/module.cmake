icgm_core_module(NAME dataset
  SOURCES
    src/core/dataset/text_table.cpp
    src/core/dataset/stamp_association.cpp
    src/core/dataset/trajectory.cpp
    src/core/dataset/depth_image.cpp
    src/core/dataset/tum_dataset.cpp
    src/core/dataset/camera_options.cpp
  DEPS icgm_core_common opencv_core opencv_imgcodecs Eigen3::Eigen)

icgm_core_test(NAME dataset
  SOURCES
    test/core/dataset/trajectory_test.cpp
    test/core/dataset/stamp_association_test.cpp
    test/core/dataset/depth_image_test.cpp
    test/core/dataset/tum_dataset_test.cpp
    test/core/dataset/camera_options_test.cpp
  DEPS icgm_core_dataset opencv_imgproc)

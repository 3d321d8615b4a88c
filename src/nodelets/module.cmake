# Nodelets: thin adapters (convert -> call core -> publish), one library for the plugin XML.
add_library(icgm_slam_nodelets SHARED
  src/nodelets/sensor_calibration.cpp
  src/nodelets/nodelet_params.cpp
  src/nodelets/map_odom_tf.cpp
  src/nodelets/map_view_publisher.cpp
  src/nodelets/image_buffer.cpp
  src/nodelets/undistortion_gate.cpp
  src/nodelets/sim_publishers.cpp
  src/nodelets/map_services.cpp
  src/nodelets/extrinsic_source.cpp
  src/nodelets/navigation_tf.cpp
  src/nodelets/navigation_viz.cpp
  src/nodelets/navigation_depth.cpp
  src/nodelets/move_base_server.cpp
  src/nodelets/map_products_publisher.cpp
  src/nodelets/odometry_wait.cpp
  src/nodelets/mono_odometry_params.cpp
  src/nodelets/features_depth_sync.cpp
  src/nodelets/frame_counts.cpp
  src/nodelets/keyframe_outlet.cpp
  src/nodelets/keyframe_intake.cpp
  src/nodelets/registration_params.cpp
  src/nodelets/frontend_frame.cpp
  src/nodelets/registration_outputs.cpp
  src/nodelets/fused_odometry_outputs.cpp
  src/nodelets/feature_frames.cpp
  src/nodelets/feature_extraction_nodelet.cpp
  src/nodelets/rgbd_registration_nodelet.cpp
  src/nodelets/odometry_fusion_nodelet.cpp
  src/nodelets/map_builder_nodelet.cpp
  src/nodelets/navigation_nodelet.cpp
  src/nodelets/simulator_nodelet.cpp
  src/nodelets/openni2_camera_nodelet.cpp
  src/nodelets/mono_odometry_nodelet.cpp)
icgm_unity(icgm_slam_nodelets BATCH 8)
target_link_libraries(icgm_slam_nodelets icgm_ros_bridge icgm_core_icgm icgm_core_viz icgm_core_registration icgm_core_odometry icgm_core_slam icgm_core_nav icgm_core_sim icgm_core_sensor icgm_core_mono
  icgm_core_map_export
  ${catkin_LIBRARIES})
add_dependencies(icgm_slam_nodelets ${PROJECT_NAME}_generate_messages_cpp)
install(TARGETS icgm_slam_nodelets LIBRARY DESTINATION ${ICGM_LIB_DIR})
add_dependencies(icgm_slam_nodelets icgm_virtual_device)  # the virtual OpenNI2 device the driver can open

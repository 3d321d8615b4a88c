icgm_core_module(NAME sim
  SOURCES
    src/core/sim/sim_options.cpp
    src/core/sim/texture.cpp
    src/core/sim/texture_drawing.cpp
    src/core/sim/procedural_textures.cpp
    src/core/sim/clothing_textures.cpp
    src/core/sim/loop_route.cpp
    src/core/sim/scene.cpp
    src/core/sim/pedestrian_model.cpp
    src/core/sim/crowd_stepper.cpp
    src/core/sim/crowd.cpp
    src/core/sim/wheel_odometry.cpp
    src/core/sim/handheld_motion.cpp
    src/core/sim/motion_blur.cpp
    src/core/sim/depth_noise.cpp
    src/core/sim/ray_caster.cpp
    src/core/sim/frame_render.cpp
    src/core/sim/simulator.cpp
    src/core/sim/sim_export.cpp
    src/core/sim/frame_prefetcher.cpp
    src/core/sim/scan_render.cpp
    src/core/sim/closed_loop_simulator.cpp
    src/core/sim/close_pass_log.cpp
    src/core/sim/close_pass_escape.cpp
  DEPS icgm_core_common icgm_core_dataset ${OpenCV_LIBS} Eigen3::Eigen pthread)

icgm_core_test(NAME sim
  SOURCES
    test/core/sim/sim_options_test.cpp
    test/core/sim/loop_route_test.cpp
    test/core/sim/wheel_odometry_test.cpp
    test/core/sim/simulator_test.cpp
    test/core/sim/sim_export_test.cpp
    test/core/sim/scenario_test.cpp
    test/core/sim/frame_prefetcher_test.cpp
    test/core/sim/handheld_motion_test.cpp
    test/core/sim/motion_blur_test.cpp
    test/core/sim/handheld_scenario_test.cpp
    test/core/sim/closed_loop_simulator_test.cpp
    test/core/sim/close_pass_log_test.cpp
    test/core/sim/close_pass_escape_test.cpp
  DEPS icgm_core_sim)

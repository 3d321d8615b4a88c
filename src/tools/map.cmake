# Hybrid map tools: appearance-only place recognition over an image list, map benchmark.
icgm_tool(NAME icgm_map_benchmark
  SOURCES src/tools/map_benchmark_main.cpp
  DEPS icgm_core_map icgm_core_common)

icgm_tool(NAME icgm_place_recognition
  SOURCES src/tools/place_recognition_main.cpp src/tools/place_recognition_run.cpp
  DEPS icgm_core_place icgm_core_registration icgm_core_map icgm_core_eval icgm_core_dataset
       icgm_core_icgm icgm_core_features icgm_core_sim icgm_core_common ${OpenCV_LIBS})
target_compile_definitions(icgm_place_recognition PRIVATE ICGM_CONFIG_DIR="${PROJECT_SOURCE_DIR}/config")

icgm_tool(NAME icgm_place_benchmark
  SOURCES src/tools/place_benchmark_main.cpp
  DEPS icgm_core_place icgm_core_map icgm_core_common)

# ICGM tools: match two images and inspect ICGM, benchmark the front-end stages.
icgm_tool(NAME icgm_match
  SOURCES src/tools/icgm_match_main.cpp
  DEPS icgm_core_icgm icgm_core_features icgm_core_common ${OpenCV_LIBS})

icgm_tool(NAME icgm_benchmark
  SOURCES src/tools/icgm_benchmark_main.cpp src/tools/feature_precision_benchmark.cpp
  DEPS icgm_core_icgm icgm_core_eval icgm_core_dataset icgm_core_features icgm_core_common
       ${OpenCV_LIBS})

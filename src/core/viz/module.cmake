icgm_core_module(NAME viz
  SOURCES src/core/viz/feature_overlay.cpp
  DEPS icgm_core_icgm ${OpenCV_LIBS})

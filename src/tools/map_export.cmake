# Dense, people-free map products: static cloud (PCD / PLY) and occupancy grid of a saved map.
icgm_tool(NAME icgm_map_export
  SOURCES src/tools/map_export_main.cpp
  DEPS icgm_core_map_export icgm_core_map icgm_core_sim icgm_core_common)

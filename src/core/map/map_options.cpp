#include "core/map/map_options.h"

#include <string>

namespace icgm {

void ReadOptions(const OptionReader& reader, DictionaryOptions* o) {
  reader.ReadEnum("descriptor_type", &o->descriptor_type);
  reader.Read("new_word_distance_bits", &o->new_word_distance_bits, 0, 4096);
  reader.Read("new_word_distance_l2", &o->new_word_distance_l2, 0.0, 1e6);
  reader.Read("normalize_float_descriptors", &o->normalize_float_descriptors);
  reader.Read("coarse_cells", &o->coarse_cells, 1, 1 << 20);
  reader.Read("probe_cells", &o->probe_cells, 1, 1 << 20);
  reader.Read("stop_word_fraction", &o->stop_word_fraction, 0.0, 1.0);
  reader.Read("stop_word_min_keyframes", &o->stop_word_min_keyframes, 1, 1 << 30);
  if (o->probe_cells > o->coarse_cells) {
    throw LoadError(reader.path() + ".probe_cells: " + std::to_string(o->probe_cells) +
                    " > coarse_cells " + std::to_string(o->coarse_cells));
  }
}

void ReadOptions(const OptionReader& reader, LoopClosureOptions* o) {
  reader.Read("candidates_per_loop", &o->candidates_per_loop, 1, 100);
  reader.Read("max_loops", &o->max_loops, 1, 1000);
  reader.Read("min_score", &o->min_score, 0.0, 1.0);
  reader.Read("exclude_recent_keyframes", &o->exclude_recent_keyframes, 0, 1 << 30);
  reader.Read("min_inliers", &o->min_inliers, 3, 1 << 20);
  reader.Read("sigma_base_m", &o->sigma_base_m, 0.0, 1e6);
  reader.Read("sigma_per_m", &o->sigma_per_m, 0.0, 10.0);
  reader.Read("sigma_base_rad", &o->sigma_base_rad, 0.0, 10.0);
  reader.Read("sigma_per_m_rad", &o->sigma_per_m_rad, 0.0, 10.0);
  reader.Read("gate_sigma", &o->gate_sigma, 0.0, 1e6);
  reader.Read("agreement_m", &o->agreement_m, 0.0, 1e6);
  reader.Read("agreement_rad", &o->agreement_rad, 0.0, 3.2);
  reader.Read("alpha_mapping", &o->alpha_mapping, 0.0, 1.0);
  reader.Read("alpha_localization", &o->alpha_localization, 0.0, 1.0);
  reader.ReadEnum("correction", &o->correction);
  reader.Read("proximity_candidates", &o->proximity_candidates, 0, 1000);
  reader.Read("proximity_radius_m", &o->proximity_radius_m, 1e-6, 1e6);
  reader.Read("proximity_radius_rad", &o->proximity_radius_rad, 1e-6, 3.2);
  reader.Read("proximity_separation", &o->proximity_separation, 1, 1 << 30);
  reader.Read("start_candidates", &o->start_candidates, 0, 1000);
  reader.Read("start_min_inliers", &o->start_min_inliers, 0, 1 << 20);
  reader.Read("start_exclude_recent_keyframes", &o->start_exclude_recent_keyframes, -1, 1 << 30);
  reader.Read("max_link_translation_m", &o->max_link_translation_m, 0.0, 1e9);
  reader.Read("max_link_rad", &o->max_link_rad, 0.0, 4.0);
  if (!(o->alpha_mapping > 0.0)) {
    throw LoadError(reader.path() + ".alpha_mapping: must be > 0 (eq. 6.4 needs 0 < alpha)");
  }
}

void ReadOptions(const OptionReader& reader, MapOptions* o) {
  reader.Read("visual_sigma_m", &o->visual_sigma_m, 1e-6, 100.0);
  reader.Read("visual_sigma_rad", &o->visual_sigma_rad, 1e-6, 10.0);
  reader.Read("wheel_sigma_m", &o->wheel_sigma_m, 1e-6, 100.0);
  reader.Read("wheel_sigma_rad", &o->wheel_sigma_rad, 1e-6, 10.0);
  reader.Read("min_keyframe_features", &o->min_keyframe_features, 0, 1 << 20);
  reader.ReadEnum("visual_information", &o->visual_information);
  reader.Read("registration_floor_sigma_m", &o->registration_floor_sigma_m, 0.0, 100.0);
  reader.Read("registration_floor_sigma_rad", &o->registration_floor_sigma_rad, 0.0, 10.0);
  reader.Read("wheel_links", &o->wheel_links);
  reader.Read("wheel_link_floor_sigma_m", &o->wheel_link_floor_sigma_m, 1e-6, 100.0);
  reader.Read("wheel_link_sigma_m_per_m", &o->wheel_link_sigma_m_per_m, 0.0, 100.0);
  reader.Read("wheel_link_floor_sigma_rad", &o->wheel_link_floor_sigma_rad, 1e-6, 10.0);
  reader.Read("wheel_link_sigma_rad_per_m", &o->wheel_link_sigma_rad_per_m, 0.0, 10.0);
  reader.Read("store_depth_images", &o->store_depth_images);
  reader.Read("depth_image_downsample", &o->depth_image_downsample, 1, 16);
}

void ReadOptions(const OptionReader& reader, PoseGraphOptions* o) {
  reader.ReadEnum("loss", &o->loss);
  reader.Read("loss_scale_sigma", &o->loss_scale_sigma, 1e-6, 1e6);
  reader.Read("max_iterations", &o->max_iterations, 1, 100000);
  reader.Read("max_solver_time_s", &o->max_solver_time_s, 1e-3, 1e6);
  reader.Read("function_tolerance", &o->function_tolerance, 0.0, 1.0);
  reader.Read("fix_session_starts", &o->fix_session_starts);
}

void ReadOptions(const OptionReader& reader, MapBuilderOptions* o,
                 std::vector<std::string>* unused_keys) {
  const OptionReader dictionary = reader.Section("dictionary");
  const OptionReader loop_closure = reader.Section("loop_closure");
  const OptionReader map = reader.Section("map");
  const OptionReader pose_graph = reader.Section("pose_graph");
  ReadOptions(dictionary, &o->dictionary);
  ReadOptions(loop_closure, &o->loop_closure);
  ReadOptions(map, &o->map);
  ReadOptions(pose_graph, &o->pose_graph);
  if (unused_keys) {
    unused_keys->clear();
    for (const OptionReader* r : {&dictionary, &loop_closure, &map, &pose_graph}) {
      for (const auto& k : r->UnusedKeys()) unused_keys->push_back(k);
    }
  } else {
    OptionReader::RejectUnknownKeys({&dictionary, &loop_closure, &map, &pose_graph});
  }
}

}  // namespace icgm

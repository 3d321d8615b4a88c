// Reads the `dictionary:`, `loop_closure:`, `map:` and `pose_graph:` sections of config/map.yaml
// into the typed options of the map module, with range checks (throws LoadError naming the key).
#pragma once

#include <string>
#include <vector>

#include "core/common/option_reader.h"
#include "core/map/map_builder.h"

namespace icgm {

void ReadOptions(const OptionReader& reader, DictionaryOptions* options);
void ReadOptions(const OptionReader& reader, LoopClosureOptions* options);
void ReadOptions(const OptionReader& reader, MapOptions* options);
void ReadOptions(const OptionReader& reader, PoseGraphOptions* options);
// Root reader: the four sections above. Keys of those sections that no option reads (typos) are
// a LoadError naming them, or, when `unused_keys` is given, listed there for the caller.
void ReadOptions(const OptionReader& reader, MapBuilderOptions* options,
                 std::vector<std::string>* unused_keys = nullptr);

}  // namespace icgm

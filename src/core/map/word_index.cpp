#include "core/map/word_index.h"

#include "core/map/binary_word_index.h"
#include "core/map/float_word_index.h"

namespace icgm {

std::unique_ptr<WordIndex> WordIndex::Create(const WordIndexOptions& options) {
  if (options.binary) return std::make_unique<BinaryWordIndex>();
  return std::make_unique<FloatWordIndex>(options.coarse_cells, options.probe_cells);
}

}  // namespace icgm

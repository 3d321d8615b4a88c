// Online-incremental visual dictionary in the style of PIRF-nav 2.0 (thesis 2.3 Fig. 2.4 and
// 4.2): no offline vocabulary. Each ICGM-robust descriptor of a new keyframe is assigned to the
// nearest existing word within `new_word_distance`; otherwise it becomes a new word. An inverted
// index maps word -> keyframes, and a query is scored against all earlier keyframes with
// idf-weighted word overlap (the Appear^t votes of Fig. 2.4, weighted so frequent words count
// less):
//   idf(w) = log((N + 1) / n_w),   N keyframes, n_w keyframes containing w
//   score(q, k) = sum_{w in q and k} idf(w) / sqrt(sum_{w in q} idf(w) * sum_{w in k} idf(w))
// in [0, 1] (1: identical word sets). Query descriptors that match no word count in the query
// norm as unseen words (idf = log(N + 1)), so a new place scores low. Per keyframe norms are kept
// up to date incrementally (sum_{w in k} log n_w), so a query costs O(sum of the inverted list
// lengths of its words) and never visits keyframes that share no word.
//
// Weighted features (optional): each descriptor row may carry a weight in (0, 1] (e.g. 1 for an
// ICGM-verified feature, less for an unverified one). A word's weight in a keyframe or query is
// the largest weight of its rows, and with weights the score is the weighted cosine
//   score(q, k) = sum_{w in q and k} a_w b_w idf(w)
//                 / sqrt(sum_{w in q} a_w^2 idf(w) * sum_{w in k} b_w^2 idf(w))
// still in [0, 1] (Cauchy-Schwarz), equal to the unweighted score when all weights are 1, and
// unchanged when all weights of an image are scaled alike: images whose weights barely differ
// (ICGM verified almost nothing, so every feature weighs about the same) score as plain
// features do, to second order in the weight differences (a min(a_w, b_w) overlap would
// lose to first order, about 1 % of the score on sparse sequences).
//
// Float descriptors (SIFT, SURF) are L2-normalised before quantization when
// `normalize_float_descriptors` is set, so `new_word_distance_l2` means the same for every
// float descriptor: OpenCV's SIFT rows have norms near 512, the project's SURF rows norm 1.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/common/enum_names.h"
#include "core/common/status.h"
#include "core/map/word_index.h"

namespace icgm {

// Descriptors the dictionary holds (`dictionary.descriptor_type`): binary ones compared with
// Hamming distance, float ones with L2.
enum class DescriptorType { kBinary, kFloat };

template <>
struct EnumNames<DescriptorType> {
  static constexpr EnumName<DescriptorType> kNames[] = {{DescriptorType::kBinary, "binary"},
                                                        {DescriptorType::kFloat, "float"}};
};

struct DictionaryOptions {
  DescriptorType descriptor_type = DescriptorType::kBinary;
  int new_word_distance_bits = 40;         // binary: farther than this from all words -> new word
  double new_word_distance_l2 = 0.3;       // float descriptors (unit-norm when normalised)
  bool normalize_float_descriptors = true; // L2-normalise float rows before quantization
  int coarse_cells = 256;                  // float index, see WordIndexOptions
  int probe_cells = 8;
  // Words seen in more than this fraction of keyframes are skipped when scoring (stop words),
  // once the dictionary holds at least `stop_word_min_keyframes` keyframes.
  double stop_word_fraction = 0.5;
  int stop_word_min_keyframes = 20;
};

struct DictionaryMatch {
  int keyframe_id = -1;
  double score = 0.0;
};

// Word id per descriptor row; -1 where no word is near enough.
using WordAssignment = std::vector<int>;

class VisualDictionary {
 public:
  explicit VisualDictionary(const DictionaryOptions& options);

  // Assigns existing words; fails on descriptors of the wrong type or width.
  Status Quantize(const cv::Mat& descriptors, WordAssignment* words) const;
  // Scores earlier keyframes against a quantized query (`descriptor_count` = rows quantized);
  // returns those sharing at least one word, best first, at most `max_results` (0: all).
  // `weights` (optional, one per row of `words`, in (0, 1]): the rows' feature weights.
  std::vector<DictionaryMatch> Score(const WordAssignment& words, int max_results = 0,
                                     const std::vector<float>* weights = nullptr) const;
  // Quantize + Score.
  Status Query(const cv::Mat& descriptors, std::vector<DictionaryMatch>* matches,
               int max_results = 0) const;
  // Adds a keyframe: unmatched descriptors become new words. Ids must increase strictly.
  // `words` (optional) receives the final assignment. `known` (optional) is a Quantize result for
  // these descriptors from this dictionary state; only its unmatched rows are searched again.
  // `weights` (optional, one per row, in (0, 1]): the rows' feature weights (else all 1).
  Status Add(int keyframe_id, const cv::Mat& descriptors, WordAssignment* words = nullptr,
             const WordAssignment* known = nullptr, const std::vector<float>* weights = nullptr);

  // Replays a recorded assignment (Keyframe::word_ids from an earlier run of this dictionary):
  // an id equal to the current word count creates that word from its row, smaller ids reuse
  // existing words. No search, so loading a map rebuilds its dictionary quickly and exactly.
  // Fails, changing nothing, when the assignment does not fit this dictionary's state.
  Status AddAssigned(int keyframe_id, const cv::Mat& descriptors, const WordAssignment& words);

  int num_words() const { return index_->size(); }
  int num_keyframes() const { return static_cast<int>(documents_.size()); }
  // Approximate heap footprint of words, index and inverted lists.
  size_t MemoryBytes() const;
  const DictionaryOptions& options() const { return options_; }

 private:
  struct Document {
    int keyframe_id;
    std::vector<int> words;      // unique
    std::vector<float> weights;  // per entry of words
    double sum_weight = 0.0;     // sum over words of b_w^2
    double sum_log_n = 0.0;      // sum over words of b_w^2 log n_w (kept current)
  };
  struct Posting {
    int document;
    float weight;  // b_w of the word in that document
  };
  Status CheckDescriptors(const cv::Mat& descriptors) const;
  // Float rows L2-normalised when the options ask for it; otherwise `descriptors` itself.
  cv::Mat Prepared(const cv::Mat& descriptors) const;
  // Registers a keyframe whose final word per row is known (all words exist).
  void AddDocument(int keyframe_id, const WordAssignment& words,
                   const std::vector<float>* weights);
  double MaxDistance() const;
  bool IsStopWord(int word) const;

  DictionaryOptions options_;
  std::unique_ptr<WordIndex> index_;
  std::vector<std::vector<Posting>> postings_;  // word -> documents (ascending)
  std::vector<Document> documents_;
};

}  // namespace icgm

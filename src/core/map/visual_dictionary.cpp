#include "core/map/visual_dictionary.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace icgm {

VisualDictionary::VisualDictionary(const DictionaryOptions& options) : options_(options) {
  WordIndexOptions index_options;
  index_options.binary = options.descriptor_type == DescriptorType::kBinary;
  index_options.coarse_cells = options.coarse_cells;
  index_options.probe_cells = options.probe_cells;
  index_ = WordIndex::Create(index_options);
}

double VisualDictionary::MaxDistance() const {
  return options_.descriptor_type == DescriptorType::kFloat
             ? options_.new_word_distance_l2
             : static_cast<double>(options_.new_word_distance_bits);
}

Status VisualDictionary::CheckDescriptors(const cv::Mat& descriptors) const {
  if (descriptors.empty()) return Status::Ok();
  const bool want_float = options_.descriptor_type == DescriptorType::kFloat;
  const int want_type = want_float ? CV_32FC1 : CV_8UC1;
  if (descriptors.type() != want_type) {
    return Status::Error(std::string("dictionary: descriptors must be ") +
                         (want_float ? "CV_32F (float)" : "CV_8U (binary)") +
                         " for descriptor_type '" + NameOf(options_.descriptor_type) + "'");
  }
  if (index_->dims() != 0 && descriptors.cols != index_->dims()) {
    return Status::Error("dictionary: descriptor width " + std::to_string(descriptors.cols) +
                         " differs from the dictionary's " + std::to_string(index_->dims()));
  }
  return Status::Ok();
}

cv::Mat VisualDictionary::Prepared(const cv::Mat& descriptors) const {
  if (options_.descriptor_type != DescriptorType::kFloat || !options_.normalize_float_descriptors ||
      descriptors.empty()) {
    return descriptors;
  }
  cv::Mat out = descriptors.clone();
  for (int r = 0; r < out.rows; ++r) {
    const double norm = cv::norm(out.row(r), cv::NORM_L2);
    if (norm > 0.0) out.row(r) *= 1.0 / norm;
  }
  return out;
}

Status VisualDictionary::Quantize(const cv::Mat& raw_descriptors, WordAssignment* words) const {
  const Status s = CheckDescriptors(raw_descriptors);
  if (!s.ok()) return s;
  const cv::Mat descriptors = Prepared(raw_descriptors);
  words->assign(static_cast<size_t>(descriptors.rows), -1);
  const double max_distance = MaxDistance();
  for (int r = 0; r < descriptors.rows; ++r) {
    (*words)[r] = index_->Nearest(descriptors.row(r), max_distance, nullptr);
  }
  return Status::Ok();
}

bool VisualDictionary::IsStopWord(int word) const {
  const int n = num_keyframes();
  return n >= options_.stop_word_min_keyframes &&
         static_cast<double>(postings_[word].size()) > options_.stop_word_fraction * n;
}

namespace {

// Unique words of an assignment with the largest weight of their rows (1 without weights);
// the squared weights of unmatched rows (-1) are summed into `unseen_weight`.
std::vector<std::pair<int, float>> UniqueWeighted(const WordAssignment& words,
                                                  const std::vector<float>* weights,
                                                  double* unseen_weight) {
  std::vector<std::pair<int, float>> unique;
  unique.reserve(words.size());
  double unseen = 0.0;
  for (size_t r = 0; r < words.size(); ++r) {
    const float w = weights ? (*weights)[r] : 1.f;
    if (words[r] < 0) {
      unseen += static_cast<double>(w) * w;
    } else {
      unique.emplace_back(words[r], w);
    }
  }
  // Same word: largest weight first, then keep the first of each word.
  std::sort(unique.begin(), unique.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  });
  unique.erase(std::unique(unique.begin(), unique.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; }),
               unique.end());
  if (unseen_weight) *unseen_weight = unseen;
  return unique;
}

}  // namespace

std::vector<DictionaryMatch> VisualDictionary::Score(const WordAssignment& words, int max_results,
                                                     const std::vector<float>* weights) const {
  std::vector<DictionaryMatch> out;
  const int n_docs = num_keyframes();
  if (n_docs == 0 || words.empty()) return out;
  if (weights && weights->size() != words.size()) weights = nullptr;
  const double log_n1 = std::log(n_docs + 1.0);
  double unseen = 0.0;
  const std::vector<std::pair<int, float>> unique = UniqueWeighted(words, weights, &unseen);
  double query_norm = unseen * log_n1;
  std::vector<double> overlap(static_cast<size_t>(n_docs), 0.0);
  std::vector<int> touched;
  for (const auto& [w, a] : unique) {
    const auto& posting = postings_[w];
    const double idf = log_n1 - std::log(static_cast<double>(posting.size()));
    query_norm += static_cast<double>(a) * a * idf;
    if (posting.empty() || IsStopWord(w)) continue;
    for (const Posting& p : posting) {
      if (overlap[p.document] == 0.0) touched.push_back(p.document);
      overlap[p.document] += static_cast<double>(a) * p.weight * idf;
    }
  }
  if (query_norm <= 0.0) return out;
  out.reserve(touched.size());
  for (int d : touched) {
    const Document& doc = documents_[d];
    const double doc_norm = doc.sum_weight * log_n1 - doc.sum_log_n;
    if (doc_norm <= 0.0 || overlap[d] <= 0.0) continue;
    out.push_back({doc.keyframe_id, overlap[d] / std::sqrt(query_norm * doc_norm)});
  }
  const auto better = [](const DictionaryMatch& a, const DictionaryMatch& b) {
    return a.score > b.score || (a.score == b.score && a.keyframe_id < b.keyframe_id);
  };
  if (max_results > 0 && static_cast<int>(out.size()) > max_results) {
    std::partial_sort(out.begin(), out.begin() + max_results, out.end(), better);
    out.resize(static_cast<size_t>(max_results));
  } else {
    std::sort(out.begin(), out.end(), better);
  }
  return out;
}

Status VisualDictionary::Query(const cv::Mat& descriptors, std::vector<DictionaryMatch>* matches,
                               int max_results) const {
  WordAssignment words;
  const Status s = Quantize(descriptors, &words);
  if (!s.ok()) return s;
  *matches = Score(words, max_results);
  return Status::Ok();
}

Status VisualDictionary::Add(int keyframe_id, const cv::Mat& raw_descriptors,
                             WordAssignment* words_out, const WordAssignment* known,
                             const std::vector<float>* weights) {
  if (!documents_.empty() && keyframe_id <= documents_.back().keyframe_id) {
    return Status::Error("dictionary: keyframe id " + std::to_string(keyframe_id) + " not after " +
                         std::to_string(documents_.back().keyframe_id));
  }
  const Status s = CheckDescriptors(raw_descriptors);
  if (!s.ok()) return s;
  if (weights && weights->size() != static_cast<size_t>(raw_descriptors.rows)) {
    return Status::Error("dictionary: " + std::to_string(weights->size()) + " weights for " +
                         std::to_string(raw_descriptors.rows) + " descriptors");
  }
  const cv::Mat descriptors = Prepared(raw_descriptors);
  const double max_distance = MaxDistance();
  WordAssignment words(static_cast<size_t>(descriptors.rows), -1);
  const bool reuse = known && known->size() == static_cast<size_t>(descriptors.rows);
  const int words_before = index_->size();
  for (int r = 0; r < descriptors.rows; ++r) {
    // Searching after each insertion lets near-duplicate descriptors of this keyframe share the
    // word the first of them created.
    int w = reuse ? (*known)[r] : -1;
    if (w >= words_before) w = -1;
    if (w < 0) w = index_->Nearest(descriptors.row(r), max_distance, nullptr);
    if (w < 0) {
      w = index_->Add(descriptors.row(r));
      postings_.emplace_back();
    }
    words[r] = w;
  }
  AddDocument(keyframe_id, words, weights);
  if (words_out) *words_out = std::move(words);
  return Status::Ok();
}

Status VisualDictionary::AddAssigned(int keyframe_id, const cv::Mat& raw_descriptors,
                                     const WordAssignment& words) {
  if (!documents_.empty() && keyframe_id <= documents_.back().keyframe_id) {
    return Status::Error("dictionary: keyframe id " + std::to_string(keyframe_id) + " not after " +
                         std::to_string(documents_.back().keyframe_id));
  }
  const Status s = CheckDescriptors(raw_descriptors);
  if (!s.ok()) return s;
  const cv::Mat descriptors = Prepared(raw_descriptors);
  if (words.size() != static_cast<size_t>(descriptors.rows)) {
    return Status::Error("dictionary: " + std::to_string(words.size()) + " recorded words for " +
                         std::to_string(descriptors.rows) + " descriptors");
  }
  int next_new = index_->size();
  for (int w : words) {
    if (w < 0 || w > next_new) {
      return Status::Error("dictionary: recorded word " + std::to_string(w) +
                           " does not fit a dictionary of " + std::to_string(next_new) + " words");
    }
    if (w == next_new) ++next_new;
  }
  for (int r = 0; r < descriptors.rows; ++r) {
    if (words[r] == index_->size()) {
      index_->Add(descriptors.row(r));
      postings_.emplace_back();
    }
  }
  AddDocument(keyframe_id, words, nullptr);
  return Status::Ok();
}

void VisualDictionary::AddDocument(int keyframe_id, const WordAssignment& words,
                                   const std::vector<float>* weights) {
  Document doc;
  doc.keyframe_id = keyframe_id;
  for (const auto& [w, b] : UniqueWeighted(words, weights, nullptr)) {
    doc.words.push_back(w);
    doc.weights.push_back(b);
  }
  const int doc_index = num_keyframes();
  for (size_t i = 0; i < doc.words.size(); ++i) {
    auto& posting = postings_[doc.words[i]];
    const float b = doc.weights[i];
    const double old_n = static_cast<double>(posting.size());
    if (old_n > 0) {
      // n_w grows by one: every keyframe holding w sees log n_w change.
      const double delta = std::log(old_n + 1.0) - std::log(old_n);
      for (const Posting& p : posting) {
        documents_[p.document].sum_log_n += static_cast<double>(p.weight) * p.weight * delta;
      }
    }
    posting.push_back({doc_index, b});
    doc.sum_weight += static_cast<double>(b) * b;
    doc.sum_log_n += static_cast<double>(b) * b * std::log(old_n + 1.0);
  }
  documents_.push_back(std::move(doc));
}

size_t VisualDictionary::MemoryBytes() const {
  size_t bytes = index_->MemoryBytes();
  for (const auto& p : postings_) bytes += p.capacity() * sizeof(Posting) + sizeof(p);
  for (const auto& d : documents_) {
    bytes += d.words.capacity() * sizeof(int) + d.weights.capacity() * sizeof(float) + sizeof(d);
  }
  return bytes;
}

}  // namespace icgm

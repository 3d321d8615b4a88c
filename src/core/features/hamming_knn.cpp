#include "core/features/hamming_knn.h"

#include <climits>
#include <cstdint>
#include <cstring>

namespace icgm {

namespace {

// Packs a descriptor row into 64-bit words (zero padded), so the inner loop is branch-free.
std::vector<uint64_t> Pack(const cv::Mat& m, int words) {
  std::vector<uint64_t> packed(static_cast<size_t>(m.rows) * words, 0);
  for (int r = 0; r < m.rows; ++r) {
    std::memcpy(&packed[static_cast<size_t>(r) * words], m.ptr<uint8_t>(r), m.cols);
  }
  return packed;
}

template <int kWords>
__attribute__((always_inline)) inline int Distance(const uint64_t* a, const uint64_t* b,
                                                   int words) {
  int d = 0;
  const int n = kWords > 0 ? kWords : words;
  for (int w = 0; w < n; ++w) d += __builtin_popcountll(a[w] ^ b[w]);
  return d;
}

// always_inline: the body must be compiled with the caller's target (POPCNT or baseline).
template <int kWords>
__attribute__((always_inline)) inline void Search(const std::vector<uint64_t>& q, int nq,
                                                  const std::vector<uint64_t>& t, int nt, int words,
                                                  HammingKnn2* out) {
  for (int i = 0; i < nq; ++i) {
    const uint64_t* qi = &q[static_cast<size_t>(i) * words];
    int best = -1;
    int d1 = INT_MAX;
    int d2 = INT_MAX;
    for (int j = 0; j < nt; ++j) {
      const int d = Distance<kWords>(qi, &t[static_cast<size_t>(j) * words], words);
      if (d < d1) {
        d2 = d1;
        d1 = d;
        best = j;
      } else if (d < d2) {
        d2 = d;
      }
    }
    out[i].best = best;
    out[i].best_distance = best >= 0 ? d1 : 0;
    out[i].second_distance = d2;
  }
}

void SearchAll(const std::vector<uint64_t>& q, int nq, const std::vector<uint64_t>& t, int nt,
               int words, HammingKnn2* out) {
  // 32-byte descriptors (ORB, BRIEF) get a fully unrolled distance.
  if (words == 4) {
    Search<4>(q, nq, t, nt, words, out);
  } else {
    Search<0>(q, nq, t, nt, words, out);
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("popcnt"))) void SearchAllPopcnt(const std::vector<uint64_t>& q, int nq,
                                                       const std::vector<uint64_t>& t, int nt,
                                                       int words, HammingKnn2* out) {
  if (words == 4) {
    Search<4>(q, nq, t, nt, words, out);
  } else {
    Search<0>(q, nq, t, nt, words, out);
  }
}
bool HasPopcnt() {
  static const bool has = __builtin_cpu_supports("popcnt");
  return has;
}
#endif

}  // namespace

bool HammingKnn2Search(const cv::Mat& query, const cv::Mat& train, std::vector<HammingKnn2>* out) {
  out->clear();
  if (query.type() != CV_8UC1 || train.type() != CV_8UC1) return false;
  if (!query.empty() && !train.empty() && query.cols != train.cols) return false;
  out->assign(query.rows, HammingKnn2{-1, 0, INT_MAX});
  if (query.empty() || train.empty()) return true;
  const int words = (query.cols + 7) / 8;
  const std::vector<uint64_t> q = Pack(query, words);
  const std::vector<uint64_t> t = Pack(train, words);
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (HasPopcnt()) {
    SearchAllPopcnt(q, query.rows, t, train.rows, words, out->data());
    return true;
  }
#endif
  SearchAll(q, query.rows, t, train.rows, words, out->data());
  return true;
}

}  // namespace icgm

#include "core/features/hamming_knn.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

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

// The running best and second-best distance with the best's row; a tie keeps the earlier row.
__attribute__((always_inline)) inline void KeepTwoBest(int d, int row, int* best_d, int* second_d,
                                                       int* best) {
  if (d < *best_d) {
    *second_d = *best_d;
    *best_d = d;
    *best = row;
  } else if (d < *second_d) {
    *second_d = d;
  }
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
      KeepTwoBest(Distance<kWords>(qi, &t[static_cast<size_t>(j) * words], words), j, &d1, &d2,
                  &best);
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

// 32-byte descriptors with AVX2: one row per 256-bit register, bits counted per byte by a
// nibble table, eight train rows per step. Lane k of the step's distances holds train row
// j + kLaneRow[k]; each lane keeps the best, the second best and the first row with the best
// distance of its own rows, and the lanes are merged at the end, so the result equals the
// sequential search's (lowest row on ties), which then continues over the last < 8 rows.
constexpr int kLaneRow[8] = {0, 2, 1, 3, 4, 6, 5, 7};

__attribute__((target("avx2"))) inline __m256i ByteCounts(__m256i x, __m256i table,
                                                          __m256i low_nibble) {
  const __m256i lo = _mm256_and_si256(x, low_nibble);
  const __m256i hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), low_nibble);
  return _mm256_add_epi8(_mm256_shuffle_epi8(table, lo), _mm256_shuffle_epi8(table, hi));
}

// Distances of query q to train rows t[0..7] (32 bytes each), lane order kLaneRow.
__attribute__((target("avx2"))) inline __m256i EightDistances(__m256i q, const uint64_t* t,
                                                              __m256i table, __m256i low_nibble) {
  const __m256i zero = _mm256_setzero_si256();
  __m256i s[8];
  for (int r = 0; r < 8; ++r) {
    const __m256i row = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(t + 4 * r));
    s[r] = _mm256_sad_epu8(ByteCounts(_mm256_xor_si256(q, row), table, low_nibble), zero);
  }
  // Per pair of rows: the two partial sums of each 128-bit half added, one row per 64 bits.
  __m256i p[4];
  for (int r = 0; r < 4; ++r) {
    p[r] = _mm256_add_epi64(_mm256_unpacklo_epi64(s[2 * r], s[2 * r + 1]),
                            _mm256_unpackhi_epi64(s[2 * r], s[2 * r + 1]));
  }
  // Two pairs per register (32 bits each), then the halves added.
  const __m256i a = _mm256_or_si256(p[0], _mm256_slli_epi64(p[1], 32));
  const __m256i b = _mm256_or_si256(p[2], _mm256_slli_epi64(p[3], 32));
  const __m256i a_sum = _mm256_add_epi32(a, _mm256_permute2x128_si256(a, a, 0x01));
  const __m256i b_sum = _mm256_add_epi32(b, _mm256_permute2x128_si256(b, b, 0x01));
  return _mm256_permute2x128_si256(a_sum, b_sum, 0x20);
}

__attribute__((target("avx2,popcnt"))) void SearchAllAvx2(const std::vector<uint64_t>& q, int nq,
                                                          const std::vector<uint64_t>& t, int nt,
                                                          HammingKnn2* out) {
  const __m256i table = _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 0, 1, 1, 2,
                                         1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
  const __m256i low_nibble = _mm256_set1_epi8(0x0f);
  const __m256i lane_row = _mm256_setr_epi32(kLaneRow[0], kLaneRow[1], kLaneRow[2], kLaneRow[3],
                                             kLaneRow[4], kLaneRow[5], kLaneRow[6], kLaneRow[7]);
  const int blocks = nt / 8;
  for (int i = 0; i < nq; ++i) {
    const uint64_t* qi = &q[static_cast<size_t>(i) * 4];
    const __m256i qv = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(qi));
    __m256i d1 = _mm256_set1_epi32(INT_MAX), d2 = d1, row1 = _mm256_setzero_si256();
    for (int b = 0; b < blocks; ++b) {
      const __m256i d = EightDistances(qv, &t[static_cast<size_t>(b) * 32], table, low_nibble);
      const __m256i rows = _mm256_add_epi32(_mm256_set1_epi32(8 * b), lane_row);
      const __m256i better = _mm256_cmpgt_epi32(d1, d);  // d < d1
      d2 = _mm256_blendv_epi8(_mm256_min_epi32(d2, d), d1, better);
      d1 = _mm256_blendv_epi8(d1, d, better);
      row1 = _mm256_blendv_epi8(row1, rows, better);
    }
    alignas(32) int lane_d1[8], lane_d2[8], lane_row1[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane_d1), d1);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane_d2), d2);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane_row1), row1);
    // Best: the smallest lane best, lowest row on ties; second: the second smallest of all
    // lanes' best and second best (each lane's two are its two smallest).
    int best = -1, best_d = INT_MAX, second_d = INT_MAX;
    for (int k = 0; k < 8 && blocks > 0; ++k) {
      const int v = lane_d1[k];
      if (v < best_d || (v == best_d && lane_row1[k] < best)) {
        second_d = std::min(second_d, best_d);
        best_d = v;
        best = lane_row1[k];
      } else {
        second_d = std::min(second_d, v);
      }
      second_d = std::min(second_d, lane_d2[k]);
    }
    for (int j = blocks * 8; j < nt; ++j) {
      KeepTwoBest(Distance<4>(qi, &t[static_cast<size_t>(j) * 4], 4), j, &best_d, &second_d, &best);
    }
    out[i].best = best;
    out[i].best_distance = best >= 0 ? best_d : 0;
    out[i].second_distance = second_d;
  }
}

bool HasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
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
  if (words == 4 && HasAvx2()) {
    SearchAllAvx2(q, query.rows, t, train.rows, out->data());
    return true;
  }
  if (HasPopcnt()) {
    SearchAllPopcnt(q, query.rows, t, train.rows, words, out->data());
    return true;
  }
#endif
  SearchAll(q, query.rows, t, train.rows, words, out->data());
  return true;
}

}  // namespace icgm

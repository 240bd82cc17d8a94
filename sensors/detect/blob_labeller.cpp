#include "sensors/detect/blob_labeller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
#include <emmintrin.h>
#endif

namespace st {
namespace {

// First x in [x, end) with row[x] > t, or end. Background pixels are skipped 16 (16-bit) or
// 32 (8-bit) at a time: saturating subtract of t is zero exactly where the pixel is <= t.
inline int findAbove(const uint16_t* row, int x, int end, int t) {
  if (t < 0) return x < end ? x : end;
#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
  const __m128i tv = _mm_set1_epi16(static_cast<short>(static_cast<uint16_t>(t)));
  const __m128i zero = _mm_setzero_si128();
  for (; x + 16 <= end; x += 16) {
    const __m128i a = _mm_subs_epu16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x)), tv);
    const __m128i b =
        _mm_subs_epu16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x + 8)), tv);
    if (_mm_movemask_epi8(_mm_cmpeq_epi16(_mm_or_si128(a, b), zero)) != 0xFFFF) break;
  }
#endif
  for (; x < end; ++x)
    if (row[x] > t) return x;
  return end;
}

inline int findAbove(const uint8_t* row, int x, int end, int t) {
  if (t < 0) return x < end ? x : end;
#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
  const __m128i tv = _mm_set1_epi8(static_cast<char>(static_cast<uint8_t>(t)));
  const __m128i zero = _mm_setzero_si128();
  for (; x + 32 <= end; x += 32) {
    const __m128i a = _mm_subs_epu8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x)), tv);
    const __m128i b =
        _mm_subs_epu8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x + 16)), tv);
    if (_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_or_si128(a, b), zero)) != 0xFFFF) break;
  }
#endif
  for (; x < end; ++x)
    if (row[x] > t) return x;
  return end;
}

// Integer threshold equivalent to "value > thr" for integer values in [0, maxval]:
// -1 = every pixel, maxval = none.
int integerThreshold(double thr, int maxval) {
  if (!(thr < maxval)) return maxval;  // also NaN: nothing passes
  if (thr < 0) return -1;
  return static_cast<int>(std::floor(thr));
}

}  // namespace

template <typename T, typename V>
void BlobLabeller::scan(const cv::Mat& test, const cv::Mat& values, int tile, int tiles_x,
                        const std::vector<double>& thresholds) {
  runs_.clear();
  run_sum_.clear();
  run_peak_.clear();
  run_peak_x_.clear();
  parent_.clear();
  const int cols = test.cols;
  const int seg = tile > 0 ? tile : cols;
  const int maxval = std::numeric_limits<T>::max();
  thread_local std::vector<int> tint;
  tint.resize(thresholds.size());
  for (std::size_t i = 0; i < thresholds.size(); ++i)
    tint[i] = integerThreshold(thresholds[i], maxval);
  std::size_t prev_begin = 0, prev_end = 0;
  for (int y = 0; y < test.rows; ++y) {
    const T* trow = test.ptr<T>(y);
    const V* vrow = values.ptr<V>(y);
    const int* trow_thr = tint.data() + (tile > 0 ? static_cast<std::size_t>((y / tile) * tiles_x) : 0);
    const std::size_t row_begin = runs_.size();
    int start = -1, peak_x = 0;
    double sum = 0, peak = -1;
    for (int xa = 0, tx = 0; xa < cols; xa += seg, ++tx) {
      const int xb = std::min(cols, xa + seg);
      const int t = trow_thr[tx];
      int x = xa;
      while (x < xb) {
        if (start < 0) {
          x = findAbove(trow, x, xb, t);
          if (x == xb) break;
          start = x;
          sum = 0;
          peak = -1;
        }
        for (; x < xb && static_cast<int>(trow[x]) > t; ++x) {
          const double v = vrow[x];
          sum += v;
          if (v > peak) {
            peak = v;
            peak_x = x;
          }
        }
        if (x < xb) {
          addRun(y, start, x - 1, sum, peak, peak_x);
          start = -1;
        }
      }
    }
    if (start >= 0) addRun(y, start, cols - 1, sum, peak, peak_x);
    linkRows(prev_begin, prev_end, row_begin);
    prev_begin = row_begin;
    prev_end = runs_.size();
  }
  finish();
}

void BlobLabeller::labelThreshold(const cv::Mat& grey, int tile, int tiles_x,
                                  const std::vector<double>& thresholds) {
  CV_Assert(grey.channels() == 1 && (grey.depth() == CV_8U || grey.depth() == CV_16U));
  CV_Assert(!thresholds.empty());
  if (grey.depth() == CV_8U)
    scan<uint8_t, uint8_t>(grey, grey, tile, tiles_x, thresholds);
  else
    scan<uint16_t, uint16_t>(grey, grey, tile, tiles_x, thresholds);
}

void BlobLabeller::labelMask(const cv::Mat& mask, const cv::Mat& grey) {
  CV_Assert(mask.type() == CV_8UC1 && mask.size() == grey.size());
  CV_Assert(grey.channels() == 1 && (grey.depth() == CV_8U || grey.depth() == CV_16U));
  thread_local const std::vector<double> zero{0.0};
  if (grey.depth() == CV_8U)
    scan<uint8_t, uint8_t>(mask, grey, 0, 1, zero);
  else
    scan<uint8_t, uint16_t>(mask, grey, 0, 1, zero);
}

void BlobLabeller::addRun(int y, int x0, int x1, double sum, double peak, int peak_x) {
  parent_.push_back(static_cast<int>(runs_.size()));
  runs_.push_back({y, x0, x1});
  run_sum_.push_back(sum);
  run_peak_.push_back(peak);
  run_peak_x_.push_back(peak_x);
}

// Runs of the previous row [pb, pe) and of the current row [cb, end), both sorted by x,
// touch (8-connectivity) when their column ranges overlap after widening by one.
void BlobLabeller::linkRows(std::size_t pb, std::size_t pe, std::size_t cb) {
  std::size_t i = pb;
  for (std::size_t j = cb; j < runs_.size(); ++j) {
    const BlobRun& c = runs_[j];
    while (i < pe && runs_[i].x1 + 1 < c.x0) ++i;
    for (std::size_t k = i; k < pe && runs_[k].x0 <= c.x1 + 1; ++k) {
      // Union: the root of a set is its first run in raster order.
      const int a = find(static_cast<int>(k)), b = find(static_cast<int>(j));
      if (a < b)
        parent_[static_cast<std::size_t>(b)] = a;
      else if (b < a)
        parent_[static_cast<std::size_t>(a)] = b;
    }
  }
}

int BlobLabeller::find(int i) {
  while (parent_[static_cast<std::size_t>(i)] != i) {
    int& p = parent_[static_cast<std::size_t>(i)];
    p = parent_[static_cast<std::size_t>(p)];  // path halving
    i = p;
  }
  return i;
}

void BlobLabeller::finish() {
  const std::size_t n = runs_.size();
  blobs_.clear();
  run_blob_.resize(n);
  for (std::size_t r = 0; r < n; ++r) {
    const BlobRun& run = runs_[r];
    const int root = find(static_cast<int>(r));
    const int len = run.x1 - run.x0 + 1;
    if (root == static_cast<int>(r)) {  // the set's first run: a new blob
      run_blob_[r] = static_cast<int>(blobs_.size());
      Blob b;
      b.area = len;
      b.x0 = run.x0;
      b.x1 = run.x1;
      b.y0 = b.y1 = run.y;
      b.sum_raw = run_sum_[r];
      b.peak = {run_peak_x_[r], run.y};
      b.peak_raw = run_peak_[r];
      b.n_runs = 1;
      blobs_.push_back(b);
      continue;
    }
    const int id = run_blob_[static_cast<std::size_t>(root)];
    run_blob_[r] = id;
    Blob& b = blobs_[static_cast<std::size_t>(id)];
    b.area += len;
    b.x0 = std::min(b.x0, run.x0);
    b.x1 = std::max(b.x1, run.x1);
    b.y1 = run.y;
    b.sum_raw += run_sum_[r];
    if (run_peak_[r] > b.peak_raw) {  // strict: the first maximum in raster order
      b.peak_raw = run_peak_[r];
      b.peak = {run_peak_x_[r], run.y};
    }
    ++b.n_runs;
  }
  // Group the run indices by blob (counting sort, raster order kept inside a blob).
  int pos = 0;
  for (Blob& b : blobs_) {
    b.first_run = pos;
    pos += b.n_runs;
  }
  counts_.assign(blobs_.size(), 0);
  order_.resize(n);
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t id = static_cast<std::size_t>(run_blob_[r]);
    order_[static_cast<std::size_t>(blobs_[id].first_run + counts_[id]++)] = static_cast<int>(r);
  }
}

}  // namespace st

#include "nodes/lifting/numpy_argsort.hpp"

#include <numeric>
#include <utility>

namespace gslift {
namespace {

// numpy/core/src/npysort/quicksort.cpp constants.
constexpr int64_t kSmallQuicksort = 15;
constexpr int kStackSize = 128;

// Moves a[i] = tmp down the max-heap a[1..n] (1-based), as numpy's sift-down does.
void sift_down(const double* v, int64_t* a, int64_t i, int64_t n, int64_t tmp) {
  for (int64_t j = i << 1; j <= n;) {
    if (j < n && v[a[j]] < v[a[j + 1]]) j += 1;
    if (!(v[tmp] < v[a[j]])) break;
    a[i] = a[j];
    i = j;
    j += j;
  }
  a[i] = tmp;
}

// numpy/core/src/npysort/heapsort.cpp (aheapsort_), on 1-based heap indices.
void heap_argsort(const double* v, int64_t* tosort, int64_t n) {
  int64_t* a = tosort - 1;
  for (int64_t l = n >> 1; l > 0; --l) sift_down(v, a, l, n, a[l]);
  for (; n > 1;) {
    const int64_t tmp = a[n];
    a[n] = a[1];
    n -= 1;
    sift_down(v, a, 1, n, tmp);
  }
}

int most_significant_bit(uint64_t n) {
  int depth = 0;
  while (n >>= 1) depth++;
  return depth;
}

}  // namespace

std::vector<int64_t> numpy_argsort(const std::vector<double>& values) {
  const int64_t num = static_cast<int64_t>(values.size());
  std::vector<int64_t> order(values.size());
  std::iota(order.begin(), order.end(), int64_t{0});
  if (num < 2) return order;

  // Transcription of aquicksort_ (numpy/core/src/npysort/quicksort.cpp, NumPy 1.24).
  const double* v = values.data();
  int64_t* pl = order.data();
  int64_t* pr = pl + num - 1;
  int64_t* stack[kStackSize];
  int64_t** sptr = stack;
  int depth[kStackSize];
  int* psdepth = depth;
  int cdepth = most_significant_bit(static_cast<uint64_t>(num)) * 2;
  int64_t *pm, *pi, *pj, *pk;

  for (;;) {
    if (cdepth < 0) {
      heap_argsort(v, pl, pr - pl + 1);
      goto stack_pop;
    }
    while ((pr - pl) > kSmallQuicksort) {
      pm = pl + ((pr - pl) >> 1);
      if (v[*pm] < v[*pl]) std::swap(*pm, *pl);
      if (v[*pr] < v[*pm]) std::swap(*pr, *pm);
      if (v[*pm] < v[*pl]) std::swap(*pm, *pl);
      const double vp = v[*pm];
      pi = pl;
      pj = pr - 1;
      std::swap(*pm, *pj);
      for (;;) {
        do ++pi;
        while (v[*pi] < vp);
        do --pj;
        while (vp < v[*pj]);
        if (pi >= pj) break;
        std::swap(*pi, *pj);
      }
      pk = pr - 1;
      std::swap(*pi, *pk);
      // Push the larger partition, continue with the smaller.
      if (pi - pl < pr - pi) {
        *sptr++ = pi + 1;
        *sptr++ = pr;
        pr = pi - 1;
      } else {
        *sptr++ = pl;
        *sptr++ = pi - 1;
        pl = pi + 1;
      }
      *psdepth++ = --cdepth;
    }
    for (pi = pl + 1; pi <= pr; ++pi) {
      const int64_t vi = *pi;
      const double vp = v[vi];
      pj = pi;
      pk = pi - 1;
      while (pj > pl && vp < v[*pk]) *pj-- = *pk--;
      *pj = vi;
    }
  stack_pop:
    if (sptr == stack) break;
    pr = *(--sptr);
    pl = *(--sptr);
    cdepth = *(--psdepth);
  }
  return order;
}

}  // namespace gslift

// The nearest-rank percentile, shared by the ensemble's per-cell statistics and the evaluation
// lines' summaries.
#pragma once

#include <cstddef>

#include "sim/core/error.h"

namespace vf {

// The nearest-rank p-th percentile (p = 1 .. 100, in per cent) of n >= 1 values sorted
// ascending: the smallest value with at least p % of the values at or below it,
// sorted[ceil(p n / 100) - 1].
inline double nearestRankPercentile(const double* sorted, std::size_t n, int p) {
  VF_ASSERT(n > 0 && p > 0 && p <= 100);
  // ceil(p n / 100) in integers: no rounding where p n / 100 is whole.
  const std::size_t k = (static_cast<std::size_t>(p) * n + 99) / 100;
  return sorted[k - 1];
}

}  // namespace vf

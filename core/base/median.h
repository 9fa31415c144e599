// The median of a sample: the middle value, or the mean of the two middle values
// when the count is even; 0 for an empty sample.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace hrad {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace hrad

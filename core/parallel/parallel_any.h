// parallel_any: whether some item of a vector satisfies a predicate, the items read by a
// team of threads (an O(n) scan over elements whose lines are each a cache miss, between
// parallel stages, should not run on one core while the others wait).
#pragma once

#include <cstddef>
#include <vector>

namespace hrad {

/// True when pred(items[i]) holds for some i, with `threads` OpenMP threads.
template <class T, class Pred>
bool parallel_any(const std::vector<T>& items, int threads, const Pred& pred) {
  const auto n = static_cast<std::ptrdiff_t>(items.size());
  bool any = false;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(|| : any)
  for (std::ptrdiff_t i = 0; i < n; ++i) any = any || pred(items[static_cast<std::size_t>(i)]);
  return any;
}

}  // namespace hrad

// Where a solve's phases sit on the progress line's 0..1 scale, whose "time left" is
// elapsed x (1 - f) / f (core/base/progress.h): for that to be right, each phase's
// share must be its share of the run's time. The first iteration makes most of the
// links and takes most of the time (one thread, revision 4a6c734: builtin:lab's
// iterations refine 2.47 / 0.43 / 0.12 / 0.10 s and propagate 0.56 / 0.27 / 0.23 /
// 0.30 s; builtin:cabin 17.4 / 1.5 / 1.1 / 0.6 s and 2.4 / 2.3 / 1.3 / 1.9 s), so:
//  - with one iteration, refinement 0.85 and propagation 0.15;
//  - with more, iteration 1 refines over 0.6 and propagates over 0.1, and the later
//    iterations share the last 0.3 equally, 40 % refining and 60 % propagating.
// With equal shares per iteration (each 80 % refining) the estimate after the first
// refinement was 5-6 times the time left.
// A propagation's preparation (open fractions, push weights, row sums) takes 60 % of
// iteration 1's (the open fractions of every leaf: lab 0.37 of 0.56 s, cabin 1.8 of
// 2.6 s) and 15 % of a later one's (only new leaves), its sweeps the rest; the open
// fractions report their progress over the first 80 % of the preparation.
#pragma once

#include <algorithm>

namespace hrad {

class ProgressScale {
 public:
  explicit ProgressScale(int iterations) : n_(std::max(iterations, 1)) {}

  /// Iteration `it`'s refinement, `share` of it done.
  [[nodiscard]] double refine(int it, double share = 0) const {
    return start(it) + share * refine_weight(it);
  }
  /// Iteration `it`'s propagation, `share` of it done.
  [[nodiscard]] double propagate(int it, double share = 0) const {
    return start(it) + refine_weight(it) + share * propagate_weight(it);
  }
  /// Where the sweeps of iteration `it`'s propagation begin, as a share of it.
  [[nodiscard]] static double prepare_share(int it) { return it <= 1 ? 0.6 : 0.15; }

 private:
  [[nodiscard]] double start(int it) const {
    if (it <= 1) return 0;
    return kFirst + static_cast<double>(std::min(it, n_ + 1) - 2) * later();
  }
  [[nodiscard]] double later() const { return n_ > 1 ? (1 - kFirst) / (n_ - 1) : 0.0; }
  [[nodiscard]] double refine_weight(int it) const {
    if (n_ == 1) return 0.85;
    return it <= 1 ? 0.6 : 0.4 * later();
  }
  [[nodiscard]] double propagate_weight(int it) const {
    if (n_ == 1) return 0.15;
    return it <= 1 ? kFirst - 0.6 : 0.6 * later();
  }
  static constexpr double kFirst = 0.7;  // iteration 1's share when there are more
  int n_;
};

}  // namespace hrad

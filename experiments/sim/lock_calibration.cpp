#include "experiments/sim/lock_calibration.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace hrad::sim {

HandoffFit fit_handoffs(const std::vector<HandoffSample>& samples) {
  HandoffFit f;
  if (samples.empty()) return f;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const HandoffSample& s : samples) {
    const double x = s.threads - 2, y = s.handoff_ns;
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double det = n * sxx - sx * sx;
  if (det > 0) {
    f.handoff_waiter_ns = std::max(0.0, (n * sxy - sx * sy) / det);
    f.handoff_ns = std::max(0.0, (sy - f.handoff_waiter_ns * sx) / n);
  } else {
    f.handoff_ns = sy / n;
  }
  return f;
}

void spin_for_ns(double ns) {
  const auto end =
      std::chrono::steady_clock::now() + std::chrono::nanoseconds(static_cast<long>(ns));
  while (std::chrono::steady_clock::now() < end) cpu_relax();
}

std::vector<std::string> calibration_lock_names() { return {"mutex", "spin"}; }

std::vector<HandoffSample> calibrate_locks(const std::string& lock, int max_threads,
                                           double duration_s, double work_ns) {
  const int hw = static_cast<int>(std::max(2u, std::thread::hardware_concurrency()));
  const int top = std::min(max_threads, hw);
  std::vector<HandoffSample> out;
  for (int k = 2; k <= top; ++k) {
    if (lock == "mutex") {
      out.push_back(measure_handoffs<TimedMutex>(k, duration_s, work_ns));
    } else if (lock == "spin") {
      out.push_back(measure_handoffs<TimedSpinMutex>(k, duration_s, work_ns));
    } else {
      throw std::invalid_argument(fmt::format("--calibrate-locks: unknown lock '{}' (known: {})",
                                              lock, fmt::join(calibration_lock_names(), ", ")));
    }
  }
  return out;
}

}  // namespace hrad::sim

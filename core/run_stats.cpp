#include "core/run_stats.h"

#include <fmt/format.h>
#include <sys/resource.h>

namespace hrad {

std::uint64_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<std::uint64_t>(u.ru_maxrss) * 1024u;  // Linux reports KiB
}

std::string descheduled_refiner_warning(const IterationStats& is) {
  if (is.refiners.size() < 2) return "";
  for (std::size_t i = 0; i < is.refiners.size(); ++i) {
    const RefinerStats& r = is.refiners[i];
    if (r.busy_s > 0.05 && r.cpu_s < 0.8 * r.busy_s)
      return fmt::format(
          "iteration {}: refiner {} ran on a CPU for {:.0f}% of the time it was refining "
          "({:.3f} of {:.3f} s): threads waited for a core (more runnable threads than "
          "cores?), so its timings measure the sharing",
          is.iteration, i, 100 * r.cpu_s / r.busy_s, r.cpu_s, r.busy_s);
  }
  return "";
}

}  // namespace hrad

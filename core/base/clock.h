// Clocks for the run statistics: wall time since a point (steady clock), and the CPU
// time the calling thread has consumed (the kernel's per-thread clock: it stops while
// the thread is descheduled, so it shows time lost to threads sharing a core).
#pragma once

#include <chrono>
#include <ctime>

namespace hrad {

using Clock = std::chrono::steady_clock;

/// Wall seconds from t0 to t1.
inline double seconds_between(Clock::time_point t0, Clock::time_point t1) {
  return std::chrono::duration<double>(t1 - t0).count();
}

/// Wall seconds from t0 to now.
inline double seconds_since(Clock::time_point t0) { return seconds_between(t0, Clock::now()); }

/// CPU seconds this thread has run (CLOCK_THREAD_CPUTIME_ID; a system call, so
/// read it per stage, not per task).
inline double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace hrad

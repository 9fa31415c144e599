// A progress line for long runs: "iteration 2/4: refine 1.23M tasks, 310k links  43.0%
// 0:12 elapsed, ~0:16 left",
// redrawn in place with '\r' on stderr, at most 10 times per second, and only when
// stderr is a terminal, so pipes and log files stay clean. Its callback() is the
// Solver's ProgressFn (core/solver/solver.h); like that, it is meant for one thread.
#pragma once

#include "core/base/clock.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

namespace hrad {

class ProgressReporter {
 public:
  using Clock = hrad::Clock;
  using NowFn = std::function<Clock::time_point()>;

  /// Minimum time between two drawn lines (10 updates per second at most).
  static constexpr std::chrono::milliseconds kMinInterval{100};

  /// Draws on stderr when stderr is a terminal (isatty) and `quiet` is false.
  explicit ProgressReporter(bool quiet = false);
  /// For tests: draws on `out` when `enabled`, reading time from `now`.
  ProgressReporter(std::FILE* out, bool enabled, NowFn now);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// `fraction` of the whole run done, in [0,1] (clamped). Draws unless the last
  /// line was drawn less than kMinInterval ago.
  void update(const std::string& phase, double fraction);
  /// Erases the line (if one was drawn). Called by the destructor too.
  void finish();

  /// A callable forwarding to update(); valid while this reporter lives.
  [[nodiscard]] std::function<void(const std::string&, double)> callback();

  [[nodiscard]] bool enabled() const { return enabled_; }
  /// Lines drawn so far.
  [[nodiscard]] int draws() const { return draws_; }

  /// "0:07", "12:34", "1:02:03" — whole seconds, rounded down.
  [[nodiscard]] static std::string format_duration(double seconds);
  /// A count in at most 5 characters: "950", "12.3k", "1.23M", "4.56G".
  [[nodiscard]] static std::string format_count(std::uint64_t n);
  /// The text of one line (without '\r' or padding). `elapsed_s` since the start.
  [[nodiscard]] static std::string format_line(const std::string& phase, double fraction,
                                               double elapsed_s);

 private:
  std::FILE* out_;
  bool enabled_;
  NowFn now_;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  int draws_ = 0;
  std::size_t last_width_ = 0;  ///< characters of the line on screen, to blank leftovers
};

}  // namespace hrad

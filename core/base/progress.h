// A progress line for long runs: "iteration 2/4: refine 1.23M tasks, 310k links  43.0%
// 0:12 elapsed, ~0:16 left", on stderr. On a terminal it is redrawn in place with '\r',
// at most 10 times per second. Elsewhere (a pipe, `| tee log`, a log file) a run that
// lasts kLogInterval or longer prints it as a whole line every kLogInterval, so a long
// run shows what it is doing without filling the log ("hrad: progress: ..."), and a
// short one prints nothing. Its callback() is the Solver's ProgressFn
// (core/solver/solver.h); like that, it is meant for one thread.
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
  /// Off a terminal: the first line after this long, then one per this long.
  static constexpr std::chrono::seconds kLogInterval{10};

  /// How lines are shown: not at all, redrawn in place, or as whole lines (a log).
  enum class Mode { Off, Redraw, Lines };

  /// On stderr unless `quiet`: redrawn when stderr is a terminal (isatty), else lines.
  explicit ProgressReporter(bool quiet = false);
  /// For tests: draws on `out` when `enabled` (redrawn), reading time from `now`.
  ProgressReporter(std::FILE* out, bool enabled, NowFn now);
  /// For tests and callers with their own stream: `mode` on `out`.
  ProgressReporter(std::FILE* out, Mode mode, NowFn now);
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

  [[nodiscard]] bool enabled() const { return mode_ != Mode::Off; }
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
  Mode mode_;
  NowFn now_;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  int draws_ = 0;
  std::size_t last_width_ = 0;  ///< characters of the line on screen, to blank leftovers
};

}  // namespace hrad

#include "core/base/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace hrad {
namespace {

// Lines are kept within a classic 80-column terminal so '\r' redraws never wrap.
constexpr std::size_t kMaxWidth = 79;
// Room for "iteration 10/10: refine 12.3M tasks, 4.56M links" beside the figures.
constexpr std::size_t kMaxPhase = 46;
// Below these the estimate of time left is noise; it is shown as "?".
constexpr double kMinFractionForEstimate = 0.01;
constexpr double kMinSecondsForEstimate = 1.0;

}  // namespace

ProgressReporter::ProgressReporter(bool quiet)
    : ProgressReporter(stderr,
                       quiet                             ? Mode::Off
                       : ::isatty(::fileno(stderr)) == 1 ? Mode::Redraw
                                                         : Mode::Lines,
                       Clock::now) {}

ProgressReporter::ProgressReporter(std::FILE* out, bool enabled, NowFn now)
    : ProgressReporter(out, enabled ? Mode::Redraw : Mode::Off, std::move(now)) {}

ProgressReporter::ProgressReporter(std::FILE* out, Mode mode, NowFn now)
    : out_(out), mode_(mode), now_(std::move(now)), start_(now_()) {}

ProgressReporter::~ProgressReporter() { finish(); }

std::string ProgressReporter::format_duration(double seconds) {
  const long s = std::isfinite(seconds) && seconds > 0 ? static_cast<long>(seconds) : 0;
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

std::string ProgressReporter::format_count(std::uint64_t n) {
  if (n < 1000) return fmt::format("{}", n);
  const char* units = "kMGTPE";
  double v = static_cast<double>(n);
  int u = -1;
  // 999.5 and above rounds to 1000 at no decimals: one unit up ("1.00M", not "1000k").
  while (v >= 999.5 && u < 5) {
    v /= 1000;
    ++u;
  }
  const int decimals = v < 9.995 ? 2 : v < 99.95 ? 1 : 0;
  return fmt::format("{:.{}f}{}", v, decimals, units[u]);
}

std::string ProgressReporter::format_line(const std::string& phase, double fraction,
                                          double elapsed_s) {
  const double f = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  std::string left = "?";
  if (f >= kMinFractionForEstimate && elapsed_s >= kMinSecondsForEstimate)
    left = "~" + format_duration(elapsed_s * (1 - f) / f);
  std::string p = phase.size() > kMaxPhase ? phase.substr(0, kMaxPhase) : phase;
  std::string line = fmt::format("{:<{}} {:5.1f}%  {} elapsed, {} left", p, kMaxPhase, 100 * f,
                                 format_duration(elapsed_s), left);
  if (line.size() > kMaxWidth) line.resize(kMaxWidth);
  return line;
}

void ProgressReporter::update(const std::string& phase, double fraction) {
  if (mode_ == Mode::Off) return;
  const Clock::time_point now = now_();
  if (mode_ == Mode::Lines) {
    if (now - (draws_ > 0 ? last_draw_ : start_) < kLogInterval) return;
    last_draw_ = now;
    std::fprintf(out_, "hrad: progress: %s\n",
                 format_line(phase, fraction, seconds_between(start_, now)).c_str());
    std::fflush(out_);
    ++draws_;
    return;
  }
  if (draws_ > 0 && now - last_draw_ < kMinInterval) return;
  last_draw_ = now;
  const double elapsed = seconds_between(start_, now);
  const std::string line = format_line(phase, fraction, elapsed);
  const std::size_t pad = last_width_ > line.size() ? last_width_ - line.size() : 0;
  std::fprintf(out_, "\r%s%*s", line.c_str(), static_cast<int>(pad), "");
  std::fflush(out_);
  last_width_ = line.size();
  ++draws_;
}

void ProgressReporter::finish() {
  if (mode_ != Mode::Redraw || last_width_ == 0) return;
  std::fprintf(out_, "\r%*s\r", static_cast<int>(last_width_), "");
  std::fflush(out_);
  last_width_ = 0;
}

std::function<void(const std::string&, double)> ProgressReporter::callback() {
  return [this](const std::string& phase, double fraction) { update(phase, fraction); };
}

}  // namespace hrad

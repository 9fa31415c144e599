#include "core/base/progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace hrad {
namespace {

// A reporter drawing into memory, with a clock the test advances by hand.
struct Fixture {
  char* buf = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buf, &size);
  ProgressReporter::Clock::time_point now{};
  ~Fixture() {
    std::fclose(out);
    std::free(buf);
  }
  std::string text() {
    std::fflush(out);
    return std::string(buf, size);
  }
  ProgressReporter::NowFn clock() {
    return [this] { return now; };
  }
};

TEST(Progress, DisabledReporterWritesNothing) {
  Fixture f;
  {
    ProgressReporter r(f.out, false, f.clock());
    r.update("refine", 0.5);
    r.finish();
    EXPECT_EQ(r.draws(), 0);
  }
  EXPECT_EQ(f.text(), "");
}

TEST(Progress, RateLimitedToTenPerSecond) {
  Fixture f;
  ProgressReporter r(f.out, true, f.clock());
  for (int i = 0; i < 100; ++i) {  // 100 updates over one second, 10 ms apart
    r.update("refine", i / 100.0);
    f.now += std::chrono::milliseconds(10);
  }
  EXPECT_GE(r.draws(), 9);
  EXPECT_LE(r.draws(), 10);
}

TEST(Progress, LineRedrawsInPlaceAndFinishErasesIt) {
  Fixture f;
  {
    ProgressReporter r(f.out, true, f.clock());
    r.update("iteration 1: refine", 0.25);
    f.now += std::chrono::seconds(1);
    r.update("iteration 1: gather", 0.5);
  }
  const std::string s = f.text();
  EXPECT_EQ(s.front(), '\r');
  EXPECT_EQ(s.find('\n'), std::string::npos);  // never scrolls
  EXPECT_NE(s.find("iteration 1: gather"), std::string::npos);
  EXPECT_NE(s.find(" 50.0%"), std::string::npos);
  EXPECT_NE(s.find("0:01 elapsed, ~0:01 left"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\r');  // the destructor blanked the line
}

// Off a terminal (`hrad solve builtin:cabin | tee log` printed nothing for a minute): a
// whole line every ten seconds once the run has lasted ten, nothing for a short run,
// no '\r' and nothing to erase.
TEST(Progress, OffATerminalAWholeLineEveryTenSeconds) {
  Fixture f;
  {
    ProgressReporter r(f.out, ProgressReporter::Mode::Lines, f.clock());
    for (int i = 0; i < 95; ++i) {  // 95 updates over 9.5 s: a short run
      r.update("loading", 0);
      f.now += std::chrono::milliseconds(100);
    }
    EXPECT_EQ(r.draws(), 0);
    for (int i = 0; i < 300; ++i) {  // 30 s more
      r.update("iteration 1/4: propagate", 0.5);
      f.now += std::chrono::milliseconds(100);
    }
    EXPECT_EQ(r.draws(), 3);  // at 10, 20 and 30 s
  }
  const std::string s = f.text();
  EXPECT_EQ(s.find('\r'), std::string::npos) << s;
  EXPECT_EQ(s.rfind("hrad: progress: iteration 1/4: propagate", 0), 0u) << s;
  EXPECT_NE(s.find("0:10 elapsed"), std::string::npos) << s;
  EXPECT_NE(s.find("0:30 elapsed"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\n');
}

TEST(Progress, FormatDurationAndLine) {
  EXPECT_EQ(ProgressReporter::format_duration(0), "0:00");
  EXPECT_EQ(ProgressReporter::format_duration(7.9), "0:07");
  EXPECT_EQ(ProgressReporter::format_duration(754), "12:34");
  EXPECT_EQ(ProgressReporter::format_duration(3723), "1:02:03");
  EXPECT_EQ(ProgressReporter::format_duration(-5), "0:00");
  // Too early for an estimate: "?".
  EXPECT_NE(ProgressReporter::format_line("x", 0.001, 10).find("? left"), std::string::npos);
  EXPECT_NE(ProgressReporter::format_line("x", 0.5, 0.2).find("? left"), std::string::npos);
  // 25% after 30 s: 90 s left.
  EXPECT_NE(ProgressReporter::format_line("x", 0.25, 30).find("~1:30 left"), std::string::npos);
  const std::string longest(200, 'p');
  EXPECT_LE(ProgressReporter::format_line(longest, 2.0, 1e9).size(), 79u);
  EXPECT_NE(ProgressReporter::format_line("x", 2.0, 1).find("100.0%"), std::string::npos);
}

}  // namespace
}  // namespace hrad

#include "core/base/interrupt.h"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>

namespace hrad {

namespace {

std::atomic<int> g_signal{0};
thread_local MemoryBudget* t_budget = nullptr;  // the innermost on this thread
std::atomic<std::int64_t> g_first_ns{0};        // when the first signal arrived (monotonic)
static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");
static_assert(std::atomic<std::int64_t>::is_always_lock_free, "used from a signal handler");

// clock_gettime is async-signal-safe (POSIX.1-2008).
std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

extern "C" void on_interrupt(int sig) {
  const std::int64_t now = monotonic_ns();
  // The time first, so that a second signal (on another thread) never sees the flag
  // without it.
  std::int64_t unset = 0;
  g_first_ns.compare_exchange_strong(unset, now, std::memory_order_relaxed);
  int none = 0;
  if (g_signal.compare_exchange_strong(none, sig, std::memory_order_relaxed)) return;
  // Signals within kSameRequestSeconds of the first are the same request: `timeout`
  // signals the process and then its whole group, and a terminal's Ctrl-C reaches
  // every process of the foreground group. Only a later one means "now".
  if (now - g_first_ns.load(std::memory_order_relaxed) <
      static_cast<std::int64_t>(kSameRequestSeconds * 1e9))
    return;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

}  // namespace

void install_interrupt_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
  });
}

bool interrupted() { return g_signal.load(std::memory_order_relaxed) != 0; }

int interrupt_signal() { return g_signal.load(std::memory_order_relaxed); }

Interrupted::Interrupted(int signal)
    : std::runtime_error(std::string("interrupted by ") + (signal == SIGTERM  ? "SIGTERM"
                                                           : signal == SIGINT ? "SIGINT"
                                                                              : "a signal")),
      signal_(signal) {}

void throw_if_interrupted() {
  if (const int s = interrupt_signal(); s != 0) throw Interrupted(s);
  if (MemoryBudget* b = t_budget; b != nullptr && b->limit_ > 0) {
    const std::int64_t now = monotonic_ns();
    if (now < b->next_check_ns_) return;
    b->next_check_ns_ = now + 10'000'000;
    const std::uint64_t rss = resident_bytes();
    if (rss > b->start_ && rss - b->start_ > b->limit_)
      throw MemoryExceeded(fmt::format(
          "{} took more than the limit of {:.3g} GB of memory (max_memory_gb; 0 means 3/4 of "
          "this machine's memory): stopped at {:.3g} GB, before it took more",
          b->what_, static_cast<double>(b->limit_) / 1e9,
          static_cast<double>(rss - b->start_) / 1e9));
  }
}

MemoryBudget::MemoryBudget(std::uint64_t limit_bytes, std::string what)
    : limit_(limit_bytes), start_(resident_bytes()), what_(std::move(what)), outer_(t_budget) {
  t_budget = this;
}

MemoryBudget::~MemoryBudget() { t_budget = outer_; }

std::uint64_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long long size = 0, resident = 0;
  const int got = std::fscanf(f, "%llu %llu", &size, &resident);
  std::fclose(f);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  return got == 2 && page > 0 ? resident * static_cast<std::uint64_t>(page) : 0;
}

void simulate_interrupt(int signal) {
  g_first_ns.store(signal != 0 ? monotonic_ns() : 0, std::memory_order_relaxed);
  g_signal.store(signal, std::memory_order_relaxed);
}

}  // namespace hrad

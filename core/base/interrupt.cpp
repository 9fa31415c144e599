#include "core/base/interrupt.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>

namespace hrad {

namespace {

std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");

extern "C" void on_interrupt(int sig) {
  if (g_signal.exchange(sig, std::memory_order_relaxed) != 0) {
    // The second signal: the default action, now.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
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
}

void simulate_interrupt(int signal) { g_signal.store(signal, std::memory_order_relaxed); }

}  // namespace hrad

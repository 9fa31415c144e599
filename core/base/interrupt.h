// Interrupts: SIGINT and SIGTERM stop a long command at a safe point instead of killing
// it between two writes (an interrupted solve could leave solution.ply without
// stats.json, an interrupted experiment a manifest that still said "running").
//
// install_interrupt_handlers() makes the first such signal set a flag; one that comes
// more than kSameRequestSeconds later ends the process at once, as the signal's default
// action would (signals that arrive together, as `timeout` sends them to the process
// and its group, are one request). Every long loop polls interrupted() where stopping
// is safe (scene building and triangulation, the overlap checks, the solver's setup,
// refinement blocks, open fractions, push weights, row sums, propagation sweeps,
// rendering, probes, path-tracing batches, experiment runs) and unwinds with
// Interrupted, within about a second of the signal; each command then removes or marks
// what it had not finished and exits with 128 + the signal. (Commands that write at
// most one file, atomically at their end, keep the default action: experiments/main.cpp.)
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace hrad {

/// Signals closer together than this are one request.
inline constexpr double kSameRequestSeconds = 1.0;

/// Installs the handlers for SIGINT and SIGTERM (once per process; later calls do
/// nothing).
void install_interrupt_handlers();

/// True once a handled signal arrived. Cheap: one relaxed atomic load.
[[nodiscard]] bool interrupted();

/// The signal that arrived (SIGINT or SIGTERM), 0 when none did.
[[nodiscard]] int interrupt_signal();

/// What unwinds a command at a safe point after an interrupt.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal);
  [[nodiscard]] int signal() const { return signal_; }
  /// 128 + the signal: the shell's status for a process the signal ended.
  [[nodiscard]] int exit_status() const { return 128 + signal_; }

 private:
  int signal_;
};

/// Throws Interrupted when interrupted(). Not inside an OpenMP region: poll
/// interrupted() there, leave the region, then call this.
void throw_if_interrupted();

/// In a loop over many cheap steps: polls every `every` steps (a power of two).
inline void poll_interrupt(std::size_t step, std::size_t every = 4096) {
  if ((step & (every - 1)) == 0) throw_if_interrupted();
}

/// For tests: raises the flag as a signal would (0 clears it).
void simulate_interrupt(int signal);

/// A bound on the memory a phase may take while it runs (loading a scene, preparing
/// it). While one lives, throw_if_interrupted() on the same thread also compares, at
/// most every 10 ms, the process's resident set with the one at the budget's start, and
/// throws MemoryExceeded when it grew by more than the limit: the phases' own checks
/// came at their ends, and a cabin of four million polygons took 2.5 GB while loading
/// under a limit of 0.3 GB. Budgets nest (the inner one applies until it ends).
class MemoryBudget {
 public:
  /// `limit_bytes` 0: no bound; `what`: the phase, for the message ("loading the scene").
  MemoryBudget(std::uint64_t limit_bytes, std::string what);
  ~MemoryBudget();
  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

 private:
  friend void throw_if_interrupted();
  std::uint64_t limit_, start_;
  std::string what_;
  std::int64_t next_check_ns_ = 0;
  MemoryBudget* outer_;
};

/// What a phase that passed its MemoryBudget throws.
class MemoryExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The process's resident set now (/proc/self/statm), in bytes; 0 when unknown.
[[nodiscard]] std::uint64_t resident_bytes();

}  // namespace hrad

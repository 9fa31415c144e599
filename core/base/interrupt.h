// Interrupts: SIGINT and SIGTERM stop a long command at a safe point instead of killing
// it between two writes (an interrupted solve could leave solution.ply without
// stats.json, an interrupted experiment a manifest that still said "running").
//
// install_interrupt_handlers() makes the first such signal set a flag; a second one
// ends the process at once, as the signal's default action would. Long loops poll
// interrupted() where stopping is safe (between refinement blocks, sweeps, stages,
// path-tracing batches and experiment runs) and unwind with Interrupted; each command
// then removes or marks what it had not finished and exits with 128 + the signal.
#pragma once

#include <stdexcept>
#include <string>

namespace hrad {

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

/// For tests: raises the flag as a signal would (0 clears it).
void simulate_interrupt(int signal);

}  // namespace hrad

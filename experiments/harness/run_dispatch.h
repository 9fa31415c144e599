// Who runs what in an MPI sweep (mpi_sweep.h), without MPI: rank 0 hands the runs of a
// resumed or new result folder to idle worker ranks one at a time, in run order, so a
// slow run holds up only its own worker. A busy worker that has not been heard from
// (result or heartbeat) for `timeout_s` is taken for dead: its run goes back to the
// front of the queue once; a run whose second worker is lost too is given up (the
// experiment then ends "failed", and --resume runs it again). A result that arrives
// for a run already recorded (a worker taken for dead that was only slow) is dropped,
// so no run is recorded twice. Times are seconds on the caller's clock.
#pragma once

#include "experiments/harness/sweep.h"

#include <deque>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace hrad::experiment {

class RunDispatch {
 public:
  /// `pending`: the runs to do, in run order; `workers`: the worker ranks, which must
  /// say ready() within `timeout_s` of `now`.
  RunDispatch(std::vector<RunId> pending, const std::vector<int>& workers, double timeout_s,
              double now);

  /// Worker `w` says it is ready (first contact, or after its result) at time `t`.
  /// Returns the run to hand it, or nothing: it waits until a run is re-queued or the
  /// sweep ends.
  std::optional<RunId> ready(int w, double t);
  /// Any message from `w` at `t` (a heartbeat): it is alive. A worker taken for dead
  /// that speaks again was only slow: it is busy with its old run again.
  void heard(int w, double t);
  /// `w` finished `id` at `t`. True when the result is new and must be recorded; false
  /// for a run already recorded. `w` is busy no more (call ready() next).
  bool finished(int w, const RunId& id, double t);

  struct Loss {
    int worker = 0;
    std::optional<RunId> run;  ///< none: it never said ready
    double silent_s = 0;       ///< since the worker was last heard from
    bool requeued = false;     ///< false: the run was already lost once and is given up
  };
  /// The busy (and never heard from) workers silent for more than the timeout at `t`,
  /// now taken for dead.
  std::vector<Loss> check(double t);
  /// Runs for waiting (idle) workers, after check() re-queued some: (worker, run).
  std::vector<std::pair<int, RunId>> assign_waiting(double t);

  /// Nothing queued and nobody busy: the sweep is over (maybe with given-up runs).
  [[nodiscard]] bool over() const;
  /// Runs queued but no live worker to run them.
  [[nodiscard]] bool stranded() const;
  [[nodiscard]] const std::vector<RunId>& given_up() const { return given_up_; }
  [[nodiscard]] std::vector<int> idle_workers() const;
  [[nodiscard]] std::vector<int> live_workers() const;
  [[nodiscard]] bool dead(int w) const;
  /// The run `w` is busy with, if any.
  [[nodiscard]] std::optional<RunId> running(int w) const;

 private:
  struct Worker {
    enum class State { Starting, Idle, Busy, Dead } state = State::Starting;
    RunId run;
    double last_heard = 0;
    bool has_run = false;  ///< `run` was handed to it (it ever was busy)
  };
  Worker& worker(int w);
  [[nodiscard]] const Worker& worker(int w) const;

  std::deque<RunId> queue_;
  std::set<RunId> done_, lost_once_;
  std::vector<RunId> given_up_;
  std::map<int, Worker> workers_;
  double timeout_s_;
};

}  // namespace hrad::experiment

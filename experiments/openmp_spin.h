// How long hrad's idle OpenMP threads spin before they sleep.
//
// libgomp's idle threads spin GOMP_SPINCOUNT times (300,000 by default: milliseconds)
// after every parallel region and at every barrier before they sleep. On a machine that
// other processes also keep busy, a spinning thread holds a core the thread with work
// needs, and every fork and barrier then waits for a time slice: beside two busy
// processes on a 2-CPU machine, builtin:cornell's propagation took 0.28 s (0.20-0.72) on
// 2 threads against 0.07 s on one, and 0.08 s with GOMP_SPINCOUNT=10000 (0.1-0.5 ms of
// spinning); on the idle machine the lab's 2-thread run is the same either way
// (docs/scaling.md). libgomp reads the variable only while it starts, before main(), so
// hrad sets it and runs itself again, once. (From the executable's .preinit_array it
// would be too early: libc's initializer, which runs after it, resets the environment.)
#pragma once

namespace hrad::cli {

/// The spin count hrad runs with unless the user chose one (or a wait policy).
inline constexpr const char* kOpenMpSpinCount = "10000";

/// When neither OMP_WAIT_POLICY nor GOMP_SPINCOUNT is set, sets GOMP_SPINCOUNT to
/// kOpenMpSpinCount and executes the program again with the same arguments; returns when
/// it did not (a variable was set, or a library is preloaded: valgrind's and heaptrack's
/// tools would lose the new process) or could not (then without the variable).
void bound_openmp_spinning(char** argv);

}  // namespace hrad::cli

// `mpirun -np N hrad experiment CONFIG.json`: the experiment's runs spread over MPI
// ranks. Rank 0 only coordinates: it opens the result folder (result_folder.h), traces
// the accuracy references if any, hands runs to idle worker ranks one at a time
// (run_dispatch.h), appends each finished run's rows as they arrive, and at the end puts
// runs.csv and iterations.csv in run order, so the folder is the serial run's, timing
// columns apart. Ranks 1..N-1 run runs (run_executor.h) and send back their rows.
// Rank 0 computes nothing itself so that it answers a worker at once (a worker never
// waits behind a solve) and can notice a silent one; waiting, every rank sleeps between
// polls instead of spinning as MPI's blocking calls do, so it costs a core nothing.
//
// Faults: workers send a heartbeat while they solve; a busy worker silent for
// --worker-timeout seconds is taken for dead, reported on stderr and in the manifest,
// and its run handed to another worker (once). With OpenMPI that needs
// `mpirun --enable-recovery`; without it, mpirun ends the whole job when a rank dies,
// and --resume carries on (any rank count). The rows of finished runs are on disk as
// soon as they arrive, whatever ends the job.
//
// Every MPI call of hrad is in mpi_sweep.cpp; a build without MPI compiles
// mpi_sweep_off.cpp instead, in which mpi_built() is false and the rest refuses.
#pragma once

#include "experiments/harness/experiment_runner.h"

#include <cstdlib>
#include <string>
#include <vector>

namespace hrad::experiment::mpi {

/// How the worker ranks on one host use its cores.
enum class RankCores {
  Share,    ///< split the CPUs they were started with, one slice each (core_share.h)
  Inherit,  ///< keep what the launcher gave each (one rank per host, or its --bind-to)
};

struct Options {
  double worker_timeout_s = 60;  ///< silence after which a rank is taken for dead
  RankCores cores = RankCores::Share;
};

/// Whether this hrad was built with MPI (CMake option HRAD_MPI).
[[nodiscard]] bool built();

/// The number of ranks and this process's rank as the launcher announces them in the
/// environment (OpenMPI's mpirun, PMI or PMIx launchers such as srun): (1, 0) when not
/// started by one. Needs no MPI call, so it holds in a build without MPI too.
struct LaunchInfo {
  int size = 1, rank = 0;
};
[[nodiscard]] inline LaunchInfo launch_info() {
  const auto get = [](const char* name) -> int {
    const char* v = std::getenv(name);
    return v && *v ? std::atoi(v) : -1;
  };
  for (const auto& [size, rank] :
       {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
        std::pair{"PMI_SIZE", "PMI_RANK"}, std::pair{"PMIX_SIZE", "PMIX_RANK"}}) {
    const int s = get(size), r = get(rank);
    if (s >= 1 && r >= 0 && r < s) return {s, r};
  }
  return {};
}

/// Starts MPI (MPI_Init_thread, MPI_THREAD_SERIALIZED). Throws std::runtime_error in a
/// build without MPI, or when MPI cannot start.
void init();

/// Rank 0: runs the sweep as above and returns its summary (`warnings` ends with a line
/// per lost worker). Other ranks: run what rank 0 hands them until it says stop; the
/// summary counts their runs. Throws like run_experiment (rank 0; the workers are told
/// to stop first), hrad::Interrupted on a signal.
ExperimentSummary run_sweep(const ManifestInputs& inputs, const std::vector<SweepPoint>& points,
                            const RunnerSettings& settings, const Options& options);

/// Ends the process with `status`: through MPI_Finalize, or, when a rank was lost (or
/// this rank ends on an error or signal), without it, since OpenMPI's finalize would
/// wait for the lost rank for ever.
[[noreturn]] void end(int status);

}  // namespace hrad::experiment::mpi

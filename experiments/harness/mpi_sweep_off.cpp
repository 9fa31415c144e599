// mpi_sweep.h in a build without MPI (HRAD_MPI=OFF, or AUTO and no MPI found).
#include "experiments/harness/mpi_sweep.h"

#include <cstdio>
#include <stdexcept>

namespace hrad::experiment::mpi {

bool built() { return false; }

void init() {
  throw std::runtime_error(
      "this hrad was built without MPI, so each of mpirun's ranks would run the whole sweep; "
      "rebuild with MPI (Debian: libopenmpi-dev openmpi-bin; cmake -DHRAD_MPI=ON) or run "
      "without mpirun");
}

ExperimentSummary run_sweep(const ManifestInputs&, const std::vector<SweepPoint>&,
                            const RunnerSettings&, const Options&) {
  init();
  return {};
}

void end(int status) {
  std::fflush(nullptr);
  std::exit(status);
}

}  // namespace hrad::experiment::mpi

#include "experiments/openmp_spin.h"

#include <unistd.h>

#include <cstdlib>

namespace hrad::cli {

void bound_openmp_spinning(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr ||
      std::getenv("LD_PRELOAD") != nullptr)
    return;
  if (setenv("GOMP_SPINCOUNT", kOpenMpSpinCount, 0) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // not executed again: the runtime keeps its own count
}

}  // namespace hrad::cli

// Cores for the worker ranks of an MPI sweep that share a host (mpi_sweep.h): with
// `--rank-cores share`, the m workers on a host split the CPUs they were all started
// with into m contiguous slices, worker k taking the k-th (sizes differ by at most one),
// and each bounds its process to its slice before its first run, so that its OpenMP
// threads, made later, stay there. Without MPI: plain lists of CPU numbers.
#pragma once

#include <string>
#include <vector>

namespace hrad::experiment {

/// The CPUs this process may run on now (sched_getaffinity), ascending.
[[nodiscard]] std::vector<int> allowed_cpus();

/// Slice `k` of `m` of `cpus` (0 <= k < m). Throws std::invalid_argument when k or m is
/// out of range or there are fewer CPUs than slices.
[[nodiscard]] std::vector<int> cpu_slice(const std::vector<int>& cpus, int k, int m);

/// Binds this process's calling thread, and so every thread it starts later, to
/// `cpus`. Throws std::runtime_error with the system's message when refused.
void bind_to_cpus(const std::vector<int>& cpus);

}  // namespace hrad::experiment

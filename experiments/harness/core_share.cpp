#include "experiments/harness/core_share.h"

#include "core/parallel/pin_plan.h"

#include <fmt/format.h>
#include <sched.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace hrad::experiment {

std::vector<int> allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) != 0)
    throw std::runtime_error(fmt::format("sched_getaffinity: {}", std::strerror(errno)));
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

std::vector<int> cpu_slice(const std::vector<int>& cpus, int k, int m) {
  if (m < 1 || k < 0 || k >= m)
    throw std::invalid_argument(fmt::format("core share {} of {}: out of range", k, m));
  const int n = static_cast<int>(cpus.size());
  if (n < m)
    throw std::invalid_argument(
        fmt::format("{} worker ranks on this host but only {} CPUs to share", m, n));
  const auto begin = cpus.begin() + static_cast<long>(k) * n / m;
  const auto end = cpus.begin() + static_cast<long>(k + 1) * n / m;
  return {begin, end};
}

void bind_to_cpus(const std::vector<int>& cpus) {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  if (::sched_setaffinity(0, sizeof set, &set) != 0)
    throw std::runtime_error(
        fmt::format("sched_setaffinity({}): {}", format_pu_list(cpus), std::strerror(errno)));
}

}  // namespace hrad::experiment

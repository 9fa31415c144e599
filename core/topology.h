// The machine's shape as the parallel parts need it: packages, NUMA nodes, cores and
// hardware threads (PUs). topology.cpp is the only file in hrad that talks to hwloc.
//
// hwloc itself honours two environment variables, so tests and users can study
// machines they do not have: HWLOC_SYNTHETIC="node:2 core:8 pu:1" (a synthetic
// description, see lstopo(1)) and HWLOC_XMLFILE=machine.xml (a topology saved with
// `lstopo machine.xml`). Such a topology is reported with synthetic = true.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hrad {

struct NumaNodeInfo {
  int os_index = 0;         ///< the node's number as the OS (and numactl) knows it
  int package = -1;         ///< logical index of the package holding it, -1 if none
  int cores = 0;            ///< cores whose PUs lie in this node
  int pus = 0;              ///< hardware threads in this node
  std::string cpus;         ///< OS indices of those PUs, as a list: "0-7,16-23"
  std::uint64_t memory_bytes = 0;  ///< local memory (0 when unknown)
};

struct TopologyInfo {
  int packages = 0;    ///< may be 0 for synthetic topologies without a package level
  int numa_nodes = 0;  ///< at least 1
  int cores = 0;       ///< physical cores (PUs when the topology has no core level)
  int pus = 0;         ///< hardware threads
  std::string description;  ///< one line: where the topology came from, CPU model
  bool synthetic = false;   ///< true when it is not this machine's (HWLOC_SYNTHETIC, XML)
  std::vector<NumaNodeInfo> nodes;  ///< in logical order
};

/// Loads the topology (honouring HWLOC_SYNTHETIC / HWLOC_XMLFILE). Throws
/// std::runtime_error when hwloc fails.
[[nodiscard]] TopologyInfo discover_topology();

/// A short tree: a summary line, then packages with their NUMA nodes, cores and PUs.
[[nodiscard]] std::string format_topology(const TopologyInfo& t);

}  // namespace hrad

// The machine's shape as the parallel parts need it: packages, NUMA nodes, cores and
// hardware threads (PUs). topology.cpp is the only file in hrad that talks to hwloc.
//
// hwloc itself honours two environment variables, so tests and users can study
// machines they do not have: HWLOC_SYNTHETIC="node:2 core:8 pu:1" (a synthetic
// description, see lstopo(1)) and HWLOC_XMLFILE=machine.xml (a topology saved with
// `lstopo machine.xml`). Such a topology is reported with synthetic = true.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>
#include "core/base/enum_names.h"

namespace hrad {

struct NumaNodeInfo {
  int os_index = 0;                ///< the node's number as the OS (and numactl) knows it
  int package = -1;                ///< logical index of the package holding it, -1 if none
  int cores = 0;                   ///< cores whose PUs lie in this node
  int pus = 0;                     ///< hardware threads in this node
  std::string cpus;                ///< OS indices of those PUs, as a list: "0-7,16-23"
  std::uint64_t memory_bytes = 0;  ///< local memory (0 when unknown)
  /// Each core's PUs (OS indices), cores in logical order; a topology without a core
  /// level has one "core" per PU. Used by core/parallel/pin_plan.h.
  std::vector<std::vector<int>> core_pus;
};

struct TopologyInfo {
  int packages = 0;                 ///< may be 0 for synthetic topologies without a package level
  int numa_nodes = 0;               ///< at least 1
  int cores = 0;                    ///< physical cores (PUs when the topology has no core level)
  int pus = 0;                      ///< hardware threads
  std::string description;          ///< one line: where the topology came from, CPU model
  std::string cpu_model;            ///< the first package's CPU model, tidied; "" when unknown
  bool synthetic = false;           ///< true when it is not this machine's (HWLOC_SYNTHETIC, XML)
  std::vector<NumaNodeInfo> nodes;  ///< in logical order
};

/// The largest synthetic topology (HWLOC_SYNTHETIC) taken, in PUs: hwloc builds one of
/// 16,384 PUs in about a second, one of 65,536 in about 14 s, one of 262,144 in minutes.
inline constexpr std::uint64_t kMaxSyntheticPus = 65536;

/// Loads the topology (honouring HWLOC_SYNTHETIC / HWLOC_XMLFILE). Throws
/// std::runtime_error when hwloc fails or a synthetic description has more than
/// kMaxSyntheticPus PUs.
[[nodiscard]] TopologyInfo discover_topology();

/// A CPU model string as a person reads it: blanks at either end removed and runs of
/// blanks inside made one ("Processor     " -> "Processor").
[[nodiscard]] std::string tidy_cpu_model(std::string_view model);

/// A short tree: a summary line, then packages with their NUMA nodes, cores and PUs.
[[nodiscard]] std::string format_topology(const TopologyInfo& t);

/// What became of a binding request.
enum class BindOutcome {
  Applied,  ///< hwloc bound the thread or memory
  Planned,  ///< computed but not applied: the topology is not this machine's
  Failed,   ///< hwloc refused (the warning says why); the run goes on unbound
};
[[nodiscard]] const char* bind_outcome_name(BindOutcome b);  ///< "applied", ...

/// Memory placement of an arena chunk (see core/parallel/node_arena.h).
enum class MemBind {
  FirstTouch,  ///< leave it to the OS: pages land where they are first written
  Interleave,  ///< pages spread round-robin over every NUMA node
  Node,        ///< every page on one given node
};
inline constexpr EnumName<MemBind> kMemBindNames[] = {
    {MemBind::FirstTouch, "first-touch", "pages where first written"},
    {MemBind::Interleave, "interleave", "pages round-robin over the nodes"},
    {MemBind::Node, "node0", "every page on node 0"},
};
constexpr std::span<const EnumName<MemBind>> enum_names(MemBind) { return kMemBindNames; }

/// A loaded topology kept open for binding threads and memory. All binding goes
/// through here, so hwloc stays in topology.cpp. Binding calls are thread-safe
/// (hwloc allows concurrent use of a loaded topology). When the topology is not
/// this machine's (HWLOC_SYNTHETIC, HWLOC_XMLFILE), nothing is applied: the calls
/// return BindOutcome::Planned, since the PUs and nodes named do not exist here.
class Topology {
 public:
  /// Loads the topology (honouring HWLOC_SYNTHETIC / HWLOC_XMLFILE); throws
  /// std::runtime_error when hwloc fails.
  Topology();
  ~Topology();
  Topology(const Topology&) = delete;
  Topology& operator=(const Topology&) = delete;

  [[nodiscard]] const TopologyInfo& info() const { return info_; }

  /// Binds the calling thread to the PUs with these OS indices
  /// (hwloc_set_cpubind, HWLOC_CPUBIND_THREAD). On failure, `warning` says why.
  BindOutcome bind_current_thread(const std::vector<int>& pus,
                                  std::string* warning = nullptr) const;

  /// The OS indices of the PUs the calling thread may run on (hwloc_get_cpubind,
  /// HWLOC_CPUBIND_THREAD), to restore after a binding; empty when the topology is
  /// not this machine's or the OS cannot say.
  [[nodiscard]] std::vector<int> current_thread_pus() const;

  /// Binds the pages of [p, p + len) (page-aligned, not yet touched) by `how`
  /// (hwloc_set_area_membind); `node` is a logical node index for MemBind::Node.
  /// FirstTouch does nothing and returns Applied.
  BindOutcome bind_memory(void* p, std::size_t len, MemBind how, int node,
                          std::string* warning = nullptr) const;

  /// The logical NUMA node holding the (touched) page at `p`
  /// (hwloc_get_area_memlocation), or -1 when unknown (synthetic topology, page
  /// not resident, or the OS cannot say).
  [[nodiscard]] int node_of_address(const void* p) const;

 private:
  struct Handle;
  std::unique_ptr<Handle> handle_;
  TopologyInfo info_;
};

}  // namespace hrad

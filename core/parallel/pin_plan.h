// PinPlan: where each refiner (and the solver thread) should run, computed from a
// TopologyInfo, a policy and a thread count. Pure: no hwloc here, so plans can be
// tested on any topology, synthetic or described by hand; core/parallel/topology.h applies
// them (or, on a topology that is not this machine's, only reports them).
//
// | policy           | refiner i is bound to                                            |
// |------------------|------------------------------------------------------------------|
// | none             | nothing (reported as node 0: an unpinned thread has no node)     |
// | compact          | the i-th PU in logical order: node by node, core by core, so     |
// |                  | consecutive refiners share a core's PUs, then a node's cores     |
// | scatter          | one PU, consecutive refiners on different nodes (and packages):  |
// |                  | round-robin over nodes, core r of each node in round r, first PU |
// |                  | of every core before any second PU, so cores fill evenly         |
// | node-round-robin | every PU of node i mod nodes                                     |
//
// More refiners than PUs (compact, scatter) wrap around to the first slot again;
// the plan says so (`wrapped`). The solver thread (it mostly sleeps) is bound to the
// whole node of refiner 0, or to nothing with `none`. Nodes without PUs (memory-only
// nodes) are never chosen. Node numbers are logical indices into TopologyInfo::nodes.
#pragma once

#include "core/base/enum_names.h"
#include "core/parallel/topology.h"

#include <string>
#include <vector>

namespace hrad {

enum class PinPolicy { None, Compact, Scatter, NodeRoundRobin };
inline constexpr EnumName<PinPolicy> kPinPolicyNames[] = {
    {PinPolicy::None, "none", "the OS places threads"},
    {PinPolicy::Compact, "compact", "fill one core's PUs, then the next core"},
    {PinPolicy::Scatter, "scatter", "spread over packages and nodes first"},
    {PinPolicy::NodeRoundRobin, "node-round-robin", "each refiner every PU of node i mod nodes"},
};
constexpr std::span<const EnumName<PinPolicy>> enum_names(PinPolicy) { return kPinPolicyNames; }

/// One thread's binding: the PUs (OS indices; empty = unbound) and their node.
struct ThreadBinding {
  int node = 0;
  std::vector<int> pus;
};

struct PinPlan {
  PinPolicy policy = PinPolicy::None;
  std::vector<ThreadBinding> refiners;  ///< one per refiner, by worker id
  ThreadBinding solver;                 ///< the solver thread
  bool wrapped = false;                 ///< more refiners than slots: some share a PU
  /// Node of each refiner (what SchedulerConfig::worker_node and the arenas need).
  [[nodiscard]] std::vector<int> worker_nodes() const;
};

/// The plan for `threads` refiners (>= 1). Throws std::invalid_argument when the
/// topology has no PU at all.
[[nodiscard]] PinPlan make_pin_plan(const TopologyInfo& topology, PinPolicy policy, int threads);

/// Binds the calling thread as `b` says, through `topology` (core/parallel/topology.h does the
/// hwloc call): "none" when b has no PUs or there is no topology, else the
/// bind_outcome_name ("applied", "planned" on a synthetic topology, "failed" with
/// `warning` set).
const char* bind_thread(const Topology* topology, const ThreadBinding& b, std::string* warning);

/// bind_thread() for a scope: when the binding is applied, the calling thread gets
/// back the CPU set it had before when the object is destroyed (OpenMP keeps its
/// threads, and the caller's own, for later stages and later runs).
class ScopedThreadBinding {
 public:
  ScopedThreadBinding(const Topology* topology, const ThreadBinding& b,
                      std::string* warning = nullptr);
  ~ScopedThreadBinding();
  ScopedThreadBinding(const ScopedThreadBinding&) = delete;
  ScopedThreadBinding& operator=(const ScopedThreadBinding&) = delete;
  [[nodiscard]] const char* outcome() const { return outcome_; }  ///< as bind_thread

 private:
  const Topology* topology_;
  std::vector<int> previous_;  ///< empty: nothing to give back
  const char* outcome_;
};

/// "0-3,8" for {0,1,2,3,8}: the PU list as numactl and hwloc write it.
[[nodiscard]] std::string format_pu_list(std::vector<int> pus);

}  // namespace hrad

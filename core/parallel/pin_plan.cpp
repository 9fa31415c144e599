#include "core/parallel/pin_plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string_view>

namespace hrad {

std::vector<int> PinPlan::worker_nodes() const {
  std::vector<int> nodes;
  nodes.reserve(refiners.size());
  for (const ThreadBinding& b : refiners) nodes.push_back(b.node);
  return nodes;
}

std::string format_pu_list(std::vector<int> pus) {
  std::sort(pus.begin(), pus.end());
  pus.erase(std::unique(pus.begin(), pus.end()), pus.end());
  std::string s;
  for (std::size_t i = 0; i < pus.size();) {
    std::size_t j = i;
    while (j + 1 < pus.size() && pus[j + 1] == pus[j] + 1) ++j;
    if (!s.empty()) s += ',';
    s += j == i ? fmt::format("{}", pus[i]) : fmt::format("{}-{}", pus[i], pus[j]);
    i = j + 1;
  }
  return s;
}

const char* bind_thread(const Topology* topology, const ThreadBinding& b, std::string* warning) {
  if (topology == nullptr || b.pus.empty()) return "none";
  return bind_outcome_name(topology->bind_current_thread(b.pus, warning));
}

ScopedThreadBinding::ScopedThreadBinding(const Topology* topology, const ThreadBinding& b,
                                         std::string* warning)
    : topology_(topology) {
  if (topology != nullptr && !b.pus.empty()) previous_ = topology->current_thread_pus();
  outcome_ = bind_thread(topology, b, warning);
  if (std::string_view(outcome_) != "applied") previous_.clear();
}

ScopedThreadBinding::~ScopedThreadBinding() {
  if (!previous_.empty()) (void)topology_->bind_current_thread(previous_);
}

namespace {

struct Slot {
  int node;
  int pu;
};

// Nodes that have PUs, in the order scatter visits them: round-robin over packages
// (the first node of each package, then the second of each, ...), so consecutive
// refiners land on different packages as well as different nodes when they can.
std::vector<int> scatter_node_order(const TopologyInfo& t) {
  std::vector<std::pair<int, int>> key;  // (rank inside its package, node), stable by node
  std::vector<int> seen_in_package;
  for (std::size_t n = 0; n < t.nodes.size(); ++n) {
    if (t.nodes[n].core_pus.empty()) continue;
    const int p = t.nodes[n].package + 1;  // -1 (no package) becomes its own group 0
    if (static_cast<int>(seen_in_package.size()) <= p)
      seen_in_package.resize(static_cast<std::size_t>(p) + 1, 0);
    key.emplace_back(seen_in_package[static_cast<std::size_t>(p)]++, static_cast<int>(n));
  }
  std::stable_sort(key.begin(), key.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<int> order;
  for (const auto& k : key) order.push_back(k.second);
  return order;
}

std::vector<Slot> compact_slots(const TopologyInfo& t) {
  std::vector<Slot> slots;
  for (std::size_t n = 0; n < t.nodes.size(); ++n)
    for (const std::vector<int>& core : t.nodes[n].core_pus)
      for (int pu : core) slots.push_back({static_cast<int>(n), pu});
  return slots;
}

std::vector<Slot> scatter_slots(const TopologyInfo& t) {
  const std::vector<int> order = scatter_node_order(t);
  std::size_t max_cores = 0, max_pus = 0;
  for (int n : order) {
    max_cores = std::max(max_cores, t.nodes[static_cast<std::size_t>(n)].core_pus.size());
    for (const auto& core : t.nodes[static_cast<std::size_t>(n)].core_pus)
      max_pus = std::max(max_pus, core.size());
  }
  std::vector<Slot> slots;
  for (std::size_t k = 0; k < max_pus; ++k)      // k-th PU of each core
    for (std::size_t r = 0; r < max_cores; ++r)  // round r: core r of each node
      for (int n : order) {
        const auto& cores = t.nodes[static_cast<std::size_t>(n)].core_pus;
        if (r < cores.size() && k < cores[r].size()) slots.push_back({n, cores[r][k]});
      }
  return slots;
}

}  // namespace

PinPlan make_pin_plan(const TopologyInfo& t, PinPolicy policy, int threads) {
  if (threads < 1) throw std::invalid_argument("pin plan: threads must be at least 1");
  PinPlan plan;
  plan.policy = policy;
  plan.refiners.resize(static_cast<std::size_t>(threads));
  if (policy == PinPolicy::None) return plan;  // node 0, no PUs

  std::vector<int> with_pus;  // nodes that have PUs
  for (std::size_t n = 0; n < t.nodes.size(); ++n)
    if (!t.nodes[n].core_pus.empty()) with_pus.push_back(static_cast<int>(n));
  if (with_pus.empty())
    throw std::invalid_argument("pin plan: the topology has no PU in any NUMA node");
  auto node_pus = [&](int n) {
    std::vector<int> pus;
    for (const auto& core : t.nodes[static_cast<std::size_t>(n)].core_pus)
      pus.insert(pus.end(), core.begin(), core.end());
    return pus;
  };

  if (policy == PinPolicy::NodeRoundRobin) {
    for (int i = 0; i < threads; ++i) {
      const int n = with_pus[static_cast<std::size_t>(i) % with_pus.size()];
      plan.refiners[static_cast<std::size_t>(i)] = ThreadBinding{n, node_pus(n)};
    }
  } else {
    const std::vector<Slot> slots =
        policy == PinPolicy::Compact ? compact_slots(t) : scatter_slots(t);
    plan.wrapped = static_cast<std::size_t>(threads) > slots.size();
    for (int i = 0; i < threads; ++i) {
      const Slot& s = slots[static_cast<std::size_t>(i) % slots.size()];
      plan.refiners[static_cast<std::size_t>(i)] = ThreadBinding{s.node, {s.pu}};
    }
  }
  const int n0 = plan.refiners[0].node;
  plan.solver = ThreadBinding{n0, node_pus(n0)};
  return plan;
}

}  // namespace hrad

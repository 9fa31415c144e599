#include "core/parallel/topology.h"

#include <fmt/format.h>
#include <hwloc.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

namespace hrad {
namespace {

struct TopologyDeleter {
  void operator()(hwloc_topology* t) const { hwloc_topology_destroy(t); }
};
using TopologyPtr = std::unique_ptr<hwloc_topology, TopologyDeleter>;

int count(hwloc_topology_t topo, hwloc_obj_type_t type) {
  const int n = hwloc_get_nbobjs_by_type(topo, type);
  return n > 0 ? n : 0;  // -1 means "at several depths", which these types never are
}

std::string cpu_list(hwloc_const_bitmap_t set) {
  char* text = nullptr;
  if (hwloc_bitmap_list_asprintf(&text, set) < 0 || !text) return "?";
  std::string s(text);
  std::free(text);
  return s;
}

std::string cpu_model_of(hwloc_topology_t topo) {
  const char* model = nullptr;
  if (hwloc_obj_t pkg = hwloc_get_obj_by_type(topo, HWLOC_OBJ_PACKAGE, 0))
    model = hwloc_obj_get_info_by_name(pkg, "CPUModel");
  return model ? tidy_cpu_model(model) : std::string();
}

std::string describe(hwloc_topology_t topo, bool synthetic) {
  if (const char* s = std::getenv("HWLOC_SYNTHETIC"); synthetic && s && *s)
    return fmt::format("synthetic topology (HWLOC_SYNTHETIC=\"{}\")", s);
  if (const char* x = std::getenv("HWLOC_XMLFILE"); synthetic && x && *x)
    return fmt::format("topology read from {} (HWLOC_XMLFILE)", x);
  if (synthetic) return "topology not of this machine";
  const std::string model = cpu_model_of(topo);
  return model.empty() ? std::string("this machine") : fmt::format("this machine: {}", model);
}

std::string bytes_text(std::uint64_t b) {
  if (b == 0) return "memory unknown";
  return fmt::format("{:.1f} GiB", static_cast<double>(b) / (1024.0 * 1024.0 * 1024.0));
}

// The PUs a synthetic description makes: the product of its levels' counts
// ("pack:2 node:2 core:4 pu:2" -> 32), or 0 when a level's count cannot be read here
// (hwloc then judges the description itself).
std::uint64_t synthetic_pus(const std::string& text) {
  std::uint64_t pus = 1;
  bool any = false;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t begin = text.find_first_not_of(" \t", at);
    if (begin == std::string::npos) break;
    const std::size_t end = std::min(text.find_first_of(" \t", begin), text.size());
    std::string level = text.substr(begin, end - begin);
    level = level.substr(0, level.find_first_of("(["));
    const std::size_t colon = level.rfind(':');
    const std::string count = colon == std::string::npos ? level : level.substr(colon + 1);
    if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos ||
        count.size() > 9)
      return 0;
    pus = std::min<std::uint64_t>(pus * std::stoull(count), std::uint64_t{1} << 40);
    any = true;
    at = end;
  }
  return any ? pus : 0;
}

TopologyPtr load() {
  hwloc_topology_t raw = nullptr;
  if (hwloc_topology_init(&raw) != 0) throw std::runtime_error("hwloc: cannot initialise");
  TopologyPtr topo(raw);
  // hwloc_topology_load reads HWLOC_SYNTHETIC / HWLOC_XMLFILE on its own, but falls back
  // to this machine without a word when it rejects them: a study of a planned machine
  // would then describe the wrong one. So they are given explicitly, and a rejected
  // one is an error.
  if (const char* s = std::getenv("HWLOC_SYNTHETIC"); s && *s) {
    // hwloc's own build of a synthetic topology grows faster than its size: 65,536 PUs
    // took 14 s, 262,144 minutes. hrad runs at most 1024 threads.
    if (const std::uint64_t pus = synthetic_pus(s); pus > kMaxSyntheticPus)
      throw std::runtime_error(
          fmt::format("HWLOC_SYNTHETIC=\"{}\" describes {} PUs; at most {} are taken (hwloc needs "
                      "minutes to build larger ones, and a run uses at most 1024 threads)",
                      s, pus, kMaxSyntheticPus));
    if (hwloc_topology_set_synthetic(raw, s) != 0)
      throw std::runtime_error(fmt::format(
          "HWLOC_SYNTHETIC=\"{}\": hwloc does not accept this description (the form is "
          "levels with counts, e.g. \"node:2 core:8 pu:1\"); unset it to use this machine",
          s));
  } else if (const char* x = std::getenv("HWLOC_XMLFILE"); x && *x) {
    if (hwloc_topology_set_xml(raw, x) != 0)
      throw std::runtime_error(fmt::format(
          "HWLOC_XMLFILE={}: hwloc cannot read it as a topology (lstopo writes one: lstopo "
          "FILE.xml); unset it to use this machine",
          x));
  }
  if (hwloc_topology_load(raw) != 0)
    throw std::runtime_error(
        "hwloc: cannot load the topology (check HWLOC_SYNTHETIC / "
        "HWLOC_XMLFILE if set)");
  return topo;
}

// Each core's PUs inside `node` (OS indices), cores in logical order; PUs of a
// topology without cores count as one core each. One walk over the topology's PUs in
// logical order, a PU belonging to the node when its OS index is in the node's cpuset
// and to the core above it: looking each core and PU up among all of the topology's
// objects (hwloc's *_inside_cpuset calls, each a scan of bitmaps) took 41 s on a
// synthetic topology of 16,384 PUs and minutes on one of 262,144.
std::vector<std::vector<int>> core_pus(hwloc_topology_t topo, hwloc_obj_t node) {
  std::vector<std::vector<int>> cores;
  const bool has_cores = count(topo, HWLOC_OBJ_CORE) > 0;
  hwloc_obj_t current = nullptr;
  for (hwloc_obj_t pu = hwloc_get_next_obj_by_type(topo, HWLOC_OBJ_PU, nullptr); pu != nullptr;
       pu = pu->next_cousin) {
    if (!hwloc_bitmap_isset(node->cpuset, pu->os_index)) continue;
    hwloc_obj_t core = has_cores ? hwloc_get_ancestor_obj_by_type(topo, HWLOC_OBJ_CORE, pu) : pu;
    if (core == nullptr) continue;  // a PU outside every core: not one hrad can place on
    if (core != current || cores.empty()) {
      cores.emplace_back();
      current = core;
    }
    cores.back().push_back(static_cast<int>(pu->os_index));
  }
  return cores;
}

TopologyInfo info_of(hwloc_topology_t raw) {
  TopologyInfo t;
  t.packages = count(raw, HWLOC_OBJ_PACKAGE);
  t.numa_nodes = count(raw, HWLOC_OBJ_NUMANODE);
  t.pus = count(raw, HWLOC_OBJ_PU);
  t.cores = count(raw, HWLOC_OBJ_CORE);
  if (t.cores == 0) t.cores = t.pus;
  t.synthetic = hwloc_topology_is_thissystem(raw) == 0;
  t.description = describe(raw, t.synthetic);
  if (!t.synthetic) t.cpu_model = cpu_model_of(raw);

  for (int i = 0; i < t.numa_nodes; ++i) {
    hwloc_obj_t node = hwloc_get_obj_by_type(raw, HWLOC_OBJ_NUMANODE, static_cast<unsigned>(i));
    NumaNodeInfo n;
    n.os_index = static_cast<int>(node->os_index);
    if (hwloc_obj_t pkg = hwloc_get_ancestor_obj_by_type(raw, HWLOC_OBJ_PACKAGE, node))
      n.package = static_cast<int>(pkg->logical_index);
    n.core_pus = core_pus(raw, node);
    n.cores = static_cast<int>(n.core_pus.size());
    n.pus = 0;
    for (const std::vector<int>& c : n.core_pus) n.pus += static_cast<int>(c.size());
    n.cpus = cpu_list(node->cpuset);
    n.memory_bytes = node->attr ? node->attr->numanode.local_memory : 0;
    t.nodes.push_back(std::move(n));
  }
  return t;
}

}  // namespace

std::string tidy_cpu_model(std::string_view model) {
  std::string s;
  bool blank = false;
  for (const char c : model) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      blank = !s.empty();
      continue;
    }
    if (blank) s += ' ';
    blank = false;
    s += c;
  }
  return s;
}

TopologyInfo discover_topology() {
  TopologyPtr topo = load();
  return info_of(topo.get());
}

std::string format_topology(const TopologyInfo& t) {
  std::string s = t.description + "\n";
  s += fmt::format("{} package{}, {} NUMA node{}, {} core{}, {} PU{} (hardware threads)\n",
                   t.packages, t.packages == 1 ? "" : "s", t.numa_nodes,
                   t.numa_nodes == 1 ? "" : "s", t.cores, t.cores == 1 ? "" : "s", t.pus,
                   t.pus == 1 ? "" : "s");
  // Packages with their nodes, then nodes that belong to no package.
  auto node_line = [](const NumaNodeInfo& n, const char* indent) {
    return fmt::format("{}NUMA node {}: {} core{}, {} PU{} (cpus {}), {}\n", indent, n.os_index,
                       n.cores, n.cores == 1 ? "" : "s", n.pus, n.pus == 1 ? "" : "s", n.cpus,
                       bytes_text(n.memory_bytes));
  };
  for (int p = 0; p < t.packages; ++p) {
    s += fmt::format("  Package {}\n", p);
    for (const NumaNodeInfo& n : t.nodes)
      if (n.package == p) s += node_line(n, "    ");
  }
  for (const NumaNodeInfo& n : t.nodes)
    if (n.package < 0) s += node_line(n, "  ");
  return s;
}

const char* bind_outcome_name(BindOutcome b) {
  switch (b) {
    case BindOutcome::Applied: return "applied";
    case BindOutcome::Planned: return "planned";
    case BindOutcome::Failed: return "failed";
  }
  return "?";
}

struct Topology::Handle {
  TopologyPtr topo;
};

Topology::Topology() : handle_(std::make_unique<Handle>()) {
  handle_->topo = load();
  info_ = info_of(handle_->topo.get());
}

Topology::~Topology() = default;

namespace {
struct BitmapDeleter {
  void operator()(hwloc_bitmap_s* b) const { hwloc_bitmap_free(b); }
};
using BitmapPtr = std::unique_ptr<hwloc_bitmap_s, BitmapDeleter>;
BitmapPtr new_bitmap() { return BitmapPtr(hwloc_bitmap_alloc()); }
}  // namespace

BindOutcome Topology::bind_current_thread(const std::vector<int>& pus, std::string* warning) const {
  if (info_.synthetic) return BindOutcome::Planned;
  BitmapPtr set = new_bitmap();
  for (int pu : pus) hwloc_bitmap_set(set.get(), static_cast<unsigned>(pu));
  if (hwloc_set_cpubind(handle_->topo.get(), set.get(), HWLOC_CPUBIND_THREAD) != 0) {
    if (warning)
      *warning = fmt::format("cannot bind a thread to cpus {}: {}", cpu_list(set.get()),
                             std::strerror(errno));
    return BindOutcome::Failed;
  }
  return BindOutcome::Applied;
}

std::vector<int> Topology::current_thread_pus() const {
  std::vector<int> pus;
  if (info_.synthetic) return pus;
  BitmapPtr set = new_bitmap();
  if (hwloc_get_cpubind(handle_->topo.get(), set.get(), HWLOC_CPUBIND_THREAD) != 0) return pus;
  for (int i = hwloc_bitmap_first(set.get()); i >= 0; i = hwloc_bitmap_next(set.get(), i))
    pus.push_back(i);
  return pus;
}

BindOutcome Topology::bind_memory(void* p, std::size_t len, MemBind how, int node,
                                  std::string* warning) const {
  if (how == MemBind::FirstTouch) return BindOutcome::Applied;
  if (info_.synthetic) return BindOutcome::Planned;
  hwloc_topology_t topo = handle_->topo.get();
  BitmapPtr set = new_bitmap();
  hwloc_membind_policy_t policy = HWLOC_MEMBIND_BIND;
  if (how == MemBind::Interleave) {
    hwloc_bitmap_copy(set.get(), hwloc_topology_get_topology_nodeset(topo));
    policy = HWLOC_MEMBIND_INTERLEAVE;
  } else {
    hwloc_obj_t obj = hwloc_get_obj_by_type(topo, HWLOC_OBJ_NUMANODE, static_cast<unsigned>(node));
    if (!obj) {
      if (warning) *warning = fmt::format("no NUMA node {} to bind memory to", node);
      return BindOutcome::Failed;
    }
    hwloc_bitmap_copy(set.get(), obj->nodeset);
  }
  if (hwloc_set_area_membind(topo, p, len, set.get(), policy, HWLOC_MEMBIND_BYNODESET) != 0) {
    if (warning)
      *warning = fmt::format("cannot bind memory ({} to nodes {}): {}",
                             how == MemBind::Interleave ? "interleave" : "bind",
                             cpu_list(set.get()), std::strerror(errno));
    return BindOutcome::Failed;
  }
  return BindOutcome::Applied;
}

int Topology::node_of_address(const void* p) const {
  if (info_.synthetic) return -1;
  hwloc_topology_t topo = handle_->topo.get();
  BitmapPtr set = new_bitmap();
  if (hwloc_get_area_memlocation(topo, p, 1, set.get(), HWLOC_MEMBIND_BYNODESET) != 0) return -1;
  const int os = hwloc_bitmap_first(set.get());
  if (os < 0 || hwloc_bitmap_weight(set.get()) != 1) return -1;
  hwloc_obj_t obj = hwloc_get_numanode_obj_by_os_index(topo, static_cast<unsigned>(os));
  return obj ? static_cast<int>(obj->logical_index) : -1;
}

}  // namespace hrad

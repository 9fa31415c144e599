#include "core/topology.h"

#include <fmt/format.h>
#include <hwloc.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>

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

int count_inside(hwloc_topology_t topo, hwloc_const_cpuset_t set, hwloc_obj_type_t type) {
  const int n = hwloc_get_nbobjs_inside_cpuset_by_type(topo, set, type);
  return n > 0 ? n : 0;
}

std::string cpu_list(hwloc_const_bitmap_t set) {
  char* text = nullptr;
  if (hwloc_bitmap_list_asprintf(&text, set) < 0 || !text) return "?";
  std::string s(text);
  std::free(text);
  return s;
}

std::string describe(hwloc_topology_t topo, bool synthetic) {
  if (const char* s = std::getenv("HWLOC_SYNTHETIC"); synthetic && s && *s)
    return fmt::format("synthetic topology (HWLOC_SYNTHETIC=\"{}\")", s);
  if (const char* x = std::getenv("HWLOC_XMLFILE"); synthetic && x && *x)
    return fmt::format("topology read from {} (HWLOC_XMLFILE)", x);
  if (synthetic) return "topology not of this machine";
  const char* model = nullptr;
  if (hwloc_obj_t pkg = hwloc_get_obj_by_type(topo, HWLOC_OBJ_PACKAGE, 0))
    model = hwloc_obj_get_info_by_name(pkg, "CPUModel");
  return model ? fmt::format("this machine: {}", model) : std::string("this machine");
}

std::string bytes_text(std::uint64_t b) {
  if (b == 0) return "memory unknown";
  return fmt::format("{:.1f} GiB", static_cast<double>(b) / (1024.0 * 1024.0 * 1024.0));
}

}  // namespace

TopologyInfo discover_topology() {
  hwloc_topology_t raw = nullptr;
  if (hwloc_topology_init(&raw) != 0) throw std::runtime_error("hwloc: cannot initialise");
  TopologyPtr topo(raw);
  // hwloc_topology_load reads HWLOC_SYNTHETIC / HWLOC_XMLFILE on its own.
  if (hwloc_topology_load(raw) != 0)
    throw std::runtime_error("hwloc: cannot load the topology (check HWLOC_SYNTHETIC / "
                             "HWLOC_XMLFILE if set)");

  TopologyInfo t;
  t.packages = count(raw, HWLOC_OBJ_PACKAGE);
  t.numa_nodes = count(raw, HWLOC_OBJ_NUMANODE);
  t.pus = count(raw, HWLOC_OBJ_PU);
  t.cores = count(raw, HWLOC_OBJ_CORE);
  if (t.cores == 0) t.cores = t.pus;
  t.synthetic = hwloc_topology_is_thissystem(raw) == 0;
  t.description = describe(raw, t.synthetic);

  for (int i = 0; i < t.numa_nodes; ++i) {
    hwloc_obj_t node = hwloc_get_obj_by_type(raw, HWLOC_OBJ_NUMANODE, static_cast<unsigned>(i));
    NumaNodeInfo n;
    n.os_index = static_cast<int>(node->os_index);
    if (hwloc_obj_t pkg = hwloc_get_ancestor_obj_by_type(raw, HWLOC_OBJ_PACKAGE, node))
      n.package = static_cast<int>(pkg->logical_index);
    n.pus = count_inside(raw, node->cpuset, HWLOC_OBJ_PU);
    n.cores = count_inside(raw, node->cpuset, HWLOC_OBJ_CORE);
    if (n.cores == 0) n.cores = n.pus;
    n.cpus = cpu_list(node->cpuset);
    n.memory_bytes = node->attr ? node->attr->numanode.local_memory : 0;
    t.nodes.push_back(std::move(n));
  }
  return t;
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

}  // namespace hrad

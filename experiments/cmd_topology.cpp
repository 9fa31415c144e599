// `hrad topology`: the machine as hwloc sees it (honours HWLOC_SYNTHETIC / HWLOC_XMLFILE).
#include "core/topology.h"
#include "experiments/commands.h"

#include <fmt/format.h>

#include <exception>

namespace hrad::cli {

void register_topology(CLI::App& app, CommandContext& ctx) {
  CLI::App* sub = app.add_subcommand(
      "topology",
      "Print the machine's packages, NUMA nodes, cores and hardware threads (hwloc; a "
      "synthetic machine can be given with HWLOC_SYNTHETIC=\"node:2 core:8 pu:1\").");
  sub->callback([&ctx] {
    try {
      fmt::print("{}", format_topology(discover_topology()));
      ctx.status = 0;
    } catch (const std::exception& e) {
      fmt::print(stderr, "hrad: {}\n", e.what());
      ctx.status = 1;
    }
  });
}

}  // namespace hrad::cli

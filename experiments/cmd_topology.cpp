// `hrad topology`: the machine as hwloc sees it (honours HWLOC_SYNTHETIC / HWLOC_XMLFILE).
#include "core/config/options.h"
#include "core/parallel/pin_plan.h"
#include "core/parallel/topology.h"
#include "experiments/commands.h"

#include <fmt/format.h>

#include <exception>
#include <memory>
#include <string>

namespace hrad::cli {
namespace {

// The plan as `hrad solve` would apply it: one line per refiner, then the solver thread.
std::string format_pin_plan(const TopologyInfo& t, const std::string& pin, int threads) {
  if (threads <= 0) threads = t.pus;
  const PinPlan plan = make_pin_plan(t, parse_enum<PinPolicy>(pin, "pin"), threads);
  std::string s = fmt::format("pin {}, {} refiner{}{}:\n", pin, threads, threads == 1 ? "" : "s",
                              t.synthetic ? " (planned only: not this machine)" : "");
  auto line = [](const ThreadBinding& b) {
    return b.pus.empty() ? std::string("unbound (counted as node 0)")
                         : fmt::format("node {}, PUs {}", b.node, format_pu_list(b.pus));
  };
  for (std::size_t i = 0; i < plan.refiners.size(); ++i)
    s += fmt::format("  refiner {}: {}\n", i, line(plan.refiners[i]));
  s += fmt::format("  solver thread: {}\n", line(plan.solver));
  if (plan.wrapped) s += "  (more refiners than PUs: the plan wraps around)\n";
  return s;
}

}  // namespace

void register_topology(CLI::App& app, CommandContext& ctx) {
  CLI::App* sub = app.add_subcommand(
      "topology",
      "Print the machine's packages, NUMA nodes, cores and hardware threads (hwloc; a "
      "synthetic machine can be given with HWLOC_SYNTHETIC=\"node:2 core:8 pu:1\").");
  struct PlanArgs {
    std::string pin;
    int threads = 0;
  };
  auto args = std::make_shared<PlanArgs>();
  sub->add_option("--pin", args->pin,
                  "also print where `hrad solve --pin POLICY` would bind each refiner")
      ->check(CLI::IsMember({"none", "compact", "scatter", "node-round-robin"}));
  sub->add_option("-t,--threads", args->threads, "refiners for --pin (default: one per PU)")
      ->transform(integer_in(1, kMaxThreads));
  sub->callback([&ctx, args] {
    try {
      const TopologyInfo t = discover_topology();
      fmt::print("{}", format_topology(t));
      if (!args->pin.empty()) fmt::print("{}", format_pin_plan(t, args->pin, args->threads));
      ctx.status = 0;
    } catch (const std::exception& e) {
      print_error(e.what());
      ctx.status = 1;
    }
  });
}

}  // namespace hrad::cli

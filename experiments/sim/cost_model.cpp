#include "experiments/sim/cost_model.h"

#include "core/base/input_file.h"
#include "core/base/json_input.h"
#include "schedulers/scheduler.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace hrad::sim {

namespace {

const std::pair<const char*, Policy> kPolicies[] = {
    {"stack", Policy::kStack},     {"fifo", Policy::kFifo},         {"priority", Policy::kPriority},
    {"blocked", Policy::kBlocked}, {"stealing", Policy::kStealing},
};

// Registered schedulers with no Policy, each decided on. A new scheduler goes here or
// into kPolicies: simulate_test fails until every registered name is in one of them.
const char* const kNotModelled[] = {
    // Its pools follow each receiver's NUMA node: the trace records no receiver and
    // the replay has no memory placement to follow.
    "locality",
};

// The largest time a cost file may give, in ns (1,000 s), as the flags allow.
constexpr double kMaxCostNs = 1e12;

// Field name -> member, for the JSON file and its echo.
const std::pair<const char*, double CostModel::*> kFields[] = {
    {"take_op_ns", &CostModel::take_op_ns},
    {"take_task_ns", &CostModel::take_task_ns},
    {"submit_op_ns", &CostModel::submit_op_ns},
    {"submit_task_ns", &CostModel::submit_task_ns},
    {"copy_task_ns", &CostModel::copy_task_ns},
    {"local_op_ns", &CostModel::local_op_ns},
    {"local_task_ns", &CostModel::local_task_ns},
    {"steal_op_ns", &CostModel::steal_op_ns},
    {"steal_task_ns", &CostModel::steal_task_ns},
    {"block_ns", &CostModel::block_ns},
    {"task_ns", &CostModel::task_ns},
    {"start_ns", &CostModel::start_ns},
    {"slowdown", &CostModel::slowdown},
    {"slowdown_per_proc", &CostModel::slowdown_per_proc},
    {"handoff_ns", &CostModel::handoff_ns},
    {"handoff_waiter_ns", &CostModel::handoff_waiter_ns},
    {"outside_serial_share", &CostModel::outside_serial_share},
};

}  // namespace

Policy policy_from_name(const std::string& name) {
  for (const auto& [n, p] : kPolicies)
    if (name == n) return p;
  // What is registered but not modelled comes from the registry, so the message holds
  // even when kNotModelled is behind.
  std::vector<std::string> unmodelled;
  for (const std::string& n : scheduler_names())
    if (std::ranges::find(kPolicies, n, &std::pair<const char*, Policy>::first) ==
        std::end(kPolicies))
      unmodelled.push_back(n);
  const bool registered = std::ranges::find(unmodelled, name) != unmodelled.end();
  const std::string what =
      registered ? "the simulator has no model of scheduler" : "unknown scheduler";
  const std::string others =
      unmodelled.empty() ? "none" : fmt::format("{}", fmt::join(unmodelled, ", "));
  throw std::invalid_argument(
      fmt::format("{} '{}' (simulated: {}; registered but not modelled: {})", what, name,
                  fmt::join(policy_names(), ", "), others));
}

std::vector<std::string> unmodelled_schedulers() {
  return {std::begin(kNotModelled), std::end(kNotModelled)};
}

const char* policy_name(Policy p) {
  for (const auto& [n, q] : kPolicies)
    if (p == q) return n;
  return "?";
}

std::vector<std::string> policy_names() {
  std::vector<std::string> names;
  for (const auto& [n, p] : kPolicies) names.emplace_back(n);
  return names;
}

CostModel default_costs(Policy policy) {
  // Scheduler microbenchmark (experiments/micro/scheduler_bench.cpp: take(B) then
  // submit(B) in a loop, 1 thread), on the shared 2-vCPU development VM, 2026-11-22:
  // ns per task at B = 10 and 100 fitted to a/B + b; a (one take + one submit) is split
  // evenly between the two lock acquisitions, b between the copy out and the copy in.
  //   stack 11.7, 7.1 -> a 51, b 6.6     fifo 14.5, 9.3 -> a 58, b 8.4
  //   priority 104.6, 72.5 -> a 357, b 69 (heap of 4096)    blocked 13.2, 6.7 -> a 72, b 6.0
  //   stealing 18.3, 9.1 -> a 102, b 8.1 (own deque: push + pop with the fence and CAS)
  // At B = 1 the benchmark measures about 110 ns per task, twice this fit's 57 ns.
  // Steals are not in the benchmark: steal_op_ns 100 (a scan touching a remote deque) and
  // steal_task_ns 20 (one CAS on a remote cache line) are assumptions.
  // Central lock hand-offs: the 16-core machine's std::mutex taken through timed_lock
  // (costs-16core-44e96be.json, docs/simulate.md); `hrad simulate --calibrate-locks`
  // measures another machine's or lock's.
  // outside_serial_share (CostModel's default, 0.46): on the 16-core machine the stage's
  // time outside the task loop (refine_wall_s − (refine_cpu_s + idle_s) / T, all four
  // iterations of lab, blocked b10, runs.jsonl) was 122.2 ms at 1 thread and 89.2 ms at
  // 2 (means of two runs each): s = 2 × 89.2 / 122.2 − 1.
  CostModel c;
  if (policy != Policy::kStealing) {
    c.handoff_ns = 414;
    c.handoff_waiter_ns = 138;
  }
  switch (policy) {
    case Policy::kStack:
      c.take_op_ns = c.submit_op_ns = 25.5;
      c.take_task_ns = c.submit_task_ns = 3.3;
      break;
    case Policy::kFifo:
      c.take_op_ns = c.submit_op_ns = 29;
      c.take_task_ns = c.submit_task_ns = 4.2;
      break;
    case Policy::kPriority:
      c.take_op_ns = c.submit_op_ns = 178;
      c.take_task_ns = c.submit_task_ns = 34.5;
      break;
    case Policy::kBlocked:
      c.take_op_ns = c.submit_op_ns = 36;
      c.take_task_ns = 3;  // copied out under the lock
      c.copy_task_ns = 3;  // copied into a chunk before locking; the submit is O(1)
      break;
    case Policy::kStealing:
      c.take_op_ns = 25.5;  // the inbox (initial tasks), as a central stack
      c.take_task_ns = 3.3;
      c.local_op_ns = 51;
      c.local_task_ns = 4;
      c.steal_op_ns = 100;
      c.steal_task_ns = 20;
      break;
  }
  return c;
}

void load_costs(const std::filesystem::path& file, CostModel& costs) {
  check_input_file(file, "the cost file");
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the cost file");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j;
  try {
    j = parse_json_document<nlohmann::json>(text.str(), file.string(), /*comments=*/true);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  if (!j.is_object())
    throw std::runtime_error(file.string() + ": the cost file must hold one JSON object");
  for (const auto& [key, value] : j.items()) {
    double CostModel::*field = nullptr;
    for (const auto& [n, f] : kFields)
      if (key == n) field = f;
    if (!field) {
      std::vector<std::string> known;
      for (const auto& [n, f] : kFields) known.emplace_back(n);
      throw std::runtime_error(fmt::format("{}: unknown cost '{}' (known: {})", file.string(), key,
                                           fmt::join(known, ", ")));
    }
    if (!value.is_number())
      throw std::runtime_error(fmt::format("{}: '{}' must be a number", file.string(), key));
    const double v = value.get<double>();
    // The bounds of the flags that set the same costs (--take-ns ... 0 to 1e12 ns,
    // --slowdown 1e-3 to 1e3): a cost of 1e308 ns was taken, and the simulated times
    // summed to inf and their ratios to nan in the CSV.
    const std::string_view k = key;
    const auto [lo, hi] = k == "slowdown"               ? std::pair{1e-3, 1e3}
                          : k == "slowdown_per_proc"    ? std::pair{0.0, 1e3}
                          : k == "outside_serial_share" ? std::pair{0.0, 1.0}
                                                        : std::pair{0.0, kMaxCostNs};
    if (!(v >= lo && v <= hi))
      throw std::runtime_error(fmt::format("{}: '{}' must be between {:g} and {:g}, not {}",
                                           file.string(), key, lo, hi, value.dump()));
    costs.*field = v;
  }
}

std::string costs_to_json(const CostModel& costs) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [n, f] : kFields) j[n] = costs.*f;
  return j.dump();
}

}  // namespace hrad::sim

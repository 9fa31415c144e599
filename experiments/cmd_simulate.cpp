// `hrad simulate TRACE [options]`: replay a task trace (--set trace=FILE of `hrad solve`)
// as a discrete-event simulation on 1, 2, 4, ... processors and predict the refinement
// time and speed-up (experiments/sim/). Every row it prints or writes is a prediction,
// marked "simulated"; rows read from `--measured` stats.json files are marked
// "measured", and the table shows the prediction error beside them.
//
// | option          | value     | default                 | meaning                                 |
// |-----------------|-----------|-------------------------|-----------------------------------------|
// | --procs         | LIST      | 1,2,4,8,16,32,64        | processor counts to simulate            |
// | --scheduler     | NAME      | the trace's             | one of policy_names() (cost_model.h)    |
// | --block-size    | N         | the trace's             | tasks per take (0: guided)              |
// | --costs         | FILE.json | per-scheduler defaults  | cost model fields (cost_model.h);       |
// |                 |           |                         | repeatable, later files override        |
// | --take-ns       | X         | default                 | take_op_ns: lock held per take          |
// | --submit-ns     | X         | default                 | submit_op_ns: lock held per submit      |
// | --steal-ns      | X         | default                 | steal_task_ns: per stolen task          |
// | --overheads     | typical, all | typical              | block_ns, task_ns from the trace's gaps |
// | --block-ns      | X         | from --overheads        | per-block time outside the scheduler    |
// | --task-ns       | X         | from --overheads        | per-task time outside its duration      |
// | --slowdown      | X         | 1                       | task duration factor at >= 2 processors |
// | --calibrate     | TRACE2    | none                    | slowdown = work(TRACE2) / work(TRACE)   |
// | --max-task-ns   | X         | none                    | cut longer task durations to X          |
// | --scale         | X         | 1                       | trace times × X (another machine's)     |
// | --stage-stats   | STATS     | none                    | the traced run's stats.json: the stage  |
// |                 |           |                         | outside the task loop (simulator.h)     |
// | --measured      | STATS     | none (repeatable)       | stats.json of real runs to compare with |
// | --out           | FILE.csv  | none                    | write the rows as CSV (atomically)      |
// | --quiet         |           | off                     | no progress line                        |
// | --calibrate-locks | LOCK    | none                    | measure LOCK's hand-offs (no TRACE)     |
// | --lock-threads  | N         | the hardware's          | --calibrate-locks at 2 .. N threads     |
// | --lock-work-ns  | X         | 200                     | private work between two acquisitions   |
#include "core/base/atomic_file.h"
#include "core/base/input_file.h"
#include "core/base/progress.h"
#include "core/config/options.h"
#include "core/parallel/trace.h"
#include "experiments/commands.h"
#include "experiments/sim/lock_calibration.h"
#include "experiments/sim/simulator.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace hrad::cli {
namespace {

using namespace hrad::sim;

struct SimulateArgs {
  std::string trace;
  std::string procs = "1,2,4,8,16,32,64";
  std::string scheduler;
  std::optional<int> block_size;  ///< none: the trace's
  double scale = 1;
  std::vector<std::string> costs;  ///< applied in order: a later file overrides
  std::string overheads = "typical", calibrate, out;
  std::optional<double> take_ns, submit_ns, steal_ns, block_ns, task_ns, slowdown;
  std::optional<std::uint32_t> max_task_ns;
  std::vector<std::string> measured;
  std::string stage_stats;
  bool quiet = false;
  std::string calibrate_locks;
  int lock_threads = 0;
  double lock_work_ns = 200;
};

// --calibrate-locks: the hand-off costs of one lock on this machine (lock_calibration.h),
// a table per thread count and the fit as a --costs JSON object.
int run_calibrate_locks(const SimulateArgs& a) {
  const int top =
      a.lock_threads > 0 ? a.lock_threads : static_cast<int>(std::thread::hardware_concurrency());
  const std::vector<HandoffSample> samples =
      calibrate_locks(a.calibrate_locks, std::max(top, 2), 0.3, a.lock_work_ns);
  fmt::print("lock '{}', {} ns of private work between acquisitions\n", a.calibrate_locks,
             a.lock_work_ns);
  fmt::print("{:>7}  {:>11}  {:>13}  {:>12}  {:>12}\n", "threads", "handoff ns", "holder changes",
             "ns/acquire", "acquisitions");
  for (const HandoffSample& s : samples)
    fmt::print("{:>7}  {:>11.1f}  {:>13.1f}%  {:>12.1f}  {:>12}\n", s.threads, s.handoff_ns,
               100 * s.change_share, s.ns_per_acquire, s.acquisitions);
  const HandoffFit f = fit_handoffs(samples);
  if (samples.size() < 2)
    fmt::print("(one thread count only: handoff_waiter_ns needs 3 or more cores)\n");
  fmt::print("{{\"handoff_ns\": {:.1f}, \"handoff_waiter_ns\": {:.1f}}}\n", f.handoff_ns,
             f.handoff_waiter_ns);
  return 0;
}

std::vector<int> parse_procs(const std::string& text) {
  std::vector<int> procs;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    int p = 0;
    try {
      p = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || p < 1 || p > 4096)
      throw std::runtime_error(fmt::format(
          "--procs: '{}' is not a processor count (a comma-separated list of integers 1..4096, "
          "e.g. 1,2,4,8)",
          item));
    procs.push_back(p);
  }
  if (procs.empty() || text.back() == ',')
    throw std::runtime_error(
        fmt::format("--procs: '{}' is not a comma-separated list of integers", text));
  std::sort(procs.begin(), procs.end());
  procs.erase(std::unique(procs.begin(), procs.end()), procs.end());
  return procs;
}

/// One real run read from its stats.json.
struct Measured {
  std::string file;
  int threads = 0;
  std::string scheduler;
  int block_size = 0;
  std::vector<double> refine_s;  ///< per iteration
  double total_s = 0;
};

Measured read_measured(const std::string& file) {
  check_input_file(file, "the stats file");
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot open the stats file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
    Measured m;
    m.file = file;
    m.threads = j.at("config").at("threads").get<int>();
    m.scheduler = j.at("config").at("scheduler").get<std::string>();
    m.block_size = j.at("config").at("block_size").get<int>();
    for (const auto& it : j.at("iterations"))
      m.refine_s.push_back(it.at("refine_wall_s").get<double>());
    for (double s : m.refine_s) m.total_s += s;
    return m;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("{}: not an hrad stats.json ({})", file, e.what()));
  }
}

// --stage-stats: per iteration, the stage's time outside the task loop in the traced
// (1-thread) run, ns × scale. Needs the fields stats.json has since 1f17afa.
std::vector<OutsideLoop> read_outside(const std::string& file, double scale) {
  check_input_file(file, "the stats file");
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot open the stats file");
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("config").at("threads").get<int>() != 1)
      throw std::runtime_error(file + ": --stage-stats wants the stats.json of a 1-thread run");
    std::vector<OutsideLoop> out;
    for (const auto& it : j.at("iterations")) {
      OutsideLoop o;
      o.load_ns = it.at("load_s").get<double>() * 1e9 * scale;
      o.compact_ns = it.at("link_compact_s").get<double>() * 1e9 * scale;
      o.edges_ns =
          (it.at("stage_start_s").get<double>() + it.at("stage_end_s").get<double>()) * 1e9 * scale;
      out.push_back(o);
    }
    return out;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(
        fmt::format("{}: not an hrad stats.json with the stage's costs (load_s, link_compact_s, "
                    "stage_start_s, stage_end_s: revision 1f17afa or later) ({})",
                    file, e.what()));
  }
}

std::string share(double part, double whole) {
  return whole > 0 ? fmt::format("{:.1f}%", 100 * part / whole) : "-";
}

int run_simulate(const SimulateArgs& a, const std::vector<std::string>& argv) {
  // Everything is checked before the (possibly long) replay.
  const std::vector<int> procs = parse_procs(a.procs);
  std::vector<Measured> measured;
  for (const std::string& f : a.measured) measured.push_back(read_measured(f));
  const std::vector<OutsideLoop> outside =
      a.stage_stats.empty() ? std::vector<OutsideLoop>{} : read_outside(a.stage_stats, a.scale);
  std::string header;
  std::vector<TraceRecord> records = read_trace(a.trace, &header);
  if (records.empty()) throw std::runtime_error(a.trace + ": the trace has no task");
  // (read_trace checked that the header is a JSON object describing the body.)
  const nlohmann::json h = nlohmann::json::parse(header);
  const std::string scheduler =
      !a.scheduler.empty() ? a.scheduler : h.value("scheduler", std::string("stack"));
  // A name from the header is the trace's, not a flag's: say so, and what to do.
  const Policy policy = [&] {
    try {
      return policy_from_name(scheduler);
    } catch (const std::invalid_argument& e) {
      if (!a.scheduler.empty()) throw;
      throw std::invalid_argument(fmt::format(
          "{} (the trace's scheduler): {}; --scheduler picks a simulated one", a.trace, e.what()));
    }
  }();
  const int block_size = a.block_size ? *a.block_size : h.value("block_size", 1);
  if (block_size < 0)
    throw std::runtime_error(
        fmt::format("--block-size must be >= 1 (or 0: guided), not {}", block_size));
  if (!(a.scale > 0)) throw std::runtime_error(fmt::format("--scale must be > 0, not {}", a.scale));
  const int trace_threads = h.value("threads", 0);
  const std::string scene = h.value("scene", std::string());

  if (a.max_task_ns) {
    // Preemptions on a loaded machine land inside task durations (multiples of the
    // scheduler tick); cutting them keeps them off the simulated critical path.
    std::uint64_t cut = 0;
    double cut_ns = 0;
    for (TraceRecord& r : records) {
      const std::uint32_t d = r.duration_ns & ~TraceRecord::kBlockStart;
      if (d <= *a.max_task_ns) continue;
      ++cut;
      cut_ns += d - *a.max_task_ns;
      r.duration_ns = (r.duration_ns & TraceRecord::kBlockStart) | *a.max_task_ns;
    }
    fmt::print("--max-task-ns {}: cut {} task(s) by {:.6f} s in all\n", *a.max_task_ns, cut,
               cut_ns * 1e-9);
  }
  if (a.scale != 1) {
    // Another machine's speed: every recorded time (durations, starts, so the gaps and
    // start_ns too) × scale, a duration capped below the block bit.
    for (TraceRecord& r : records) {
      const std::uint32_t bit = r.duration_ns & TraceRecord::kBlockStart;
      const double d = static_cast<double>(r.duration_ns & ~TraceRecord::kBlockStart) * a.scale;
      r.duration_ns = bit | static_cast<std::uint32_t>(
                                std::min(std::round(d), double{TraceRecord::kBlockStart - 1}));
      r.start_ns =
          static_cast<std::uint64_t>(std::round(static_cast<double>(r.start_ns) * a.scale));
    }
  }
  const TaskGraph graph = build_task_graph(records, a.trace);
  if (!outside.empty() && outside.size() != graph.iterations.size())
    throw std::runtime_error(fmt::format("{} has {} iterations, the trace {}: not the traced run?",
                                         a.stage_stats, outside.size(), graph.iterations.size()));
  // Costs: the microbenchmark defaults < the trace's gaps (--overheads) < --costs FILE
  // < the flags.
  CostModel costs = default_costs(policy);
  const GapStats gaps = gap_stats(records);
  {
    const double fixed =
        policy == Policy::kStealing ? 2 * costs.local_op_ns : costs.take_op_ns + costs.submit_op_ns;
    costs.start_ns = 0;
    for (const IterationGraph& g : graph.iterations)
      costs.start_ns += static_cast<double>(g.first_start_ns);
    costs.start_ns /= static_cast<double>(graph.iterations.size());
    if (a.overheads == "typical") {
      costs.block_ns = std::max(0.0, gaps.block_median - fixed);
      costs.task_ns = 0;
    } else if (a.overheads == "all") {
      costs.block_ns = std::max(0.0, gaps.block_mean - fixed);
      costs.task_ns = gaps.task_mean;
    } else {
      throw std::runtime_error(
          fmt::format("--overheads: '{}' is not 'typical' or 'all'", a.overheads));
    }
  }
  // With the stage's own figures, its start is in stage_start_s and the first chunk's
  // load in load_s: the trace's first-task start would count them twice.
  if (!outside.empty()) costs.start_ns = 0;
  for (const std::string& file : a.costs) load_costs(file, costs);
  const std::pair<const char*, const std::optional<double>*> flags[] = {
      {"--take-ns", &a.take_ns},
      {"--submit-ns", &a.submit_ns},
      {"--steal-ns", &a.steal_ns},
      {"--block-ns", &a.block_ns},
      {"--task-ns", &a.task_ns}};
  for (const auto& [name, value] : flags)
    if (*value && !(**value >= 0))
      throw std::runtime_error(fmt::format("{} must be >= 0, not {}", name, **value));
  if (a.take_ns) costs.take_op_ns = *a.take_ns;
  if (a.submit_ns) costs.submit_op_ns = *a.submit_ns;
  if (a.steal_ns) costs.steal_task_ns = *a.steal_ns;
  if (a.block_ns) costs.block_ns = *a.block_ns;
  if (a.task_ns) costs.task_ns = *a.task_ns;
  if (a.slowdown) {
    if (!(*a.slowdown > 0))
      throw std::runtime_error(fmt::format("--slowdown must be > 0, not {}", *a.slowdown));
    costs.slowdown = *a.slowdown;
  }

  if (!a.calibrate.empty()) {
    const std::vector<TraceRecord> other = read_trace(a.calibrate, nullptr);
    const TaskGraph g2 = build_task_graph(other, a.calibrate);
    if (g2.tasks() != graph.tasks())
      fmt::print(stderr, "hrad: warning: {} has {} tasks, {} has {}: not the same run?\n",
                 a.calibrate, g2.tasks(), a.trace, graph.tasks());
    costs.slowdown = static_cast<double>(g2.work_ns()) / static_cast<double>(graph.work_ns());
  }

  fmt::print("trace {}: {} tasks in {} iterations, recorded with {} thread(s), {}, block size {}\n",
             a.trace, graph.tasks(), graph.iterations.size(), trace_threads,
             h.value("scheduler", std::string("?")), h.value("block_size", 0));
  // A duration in the unit that shows it (a critical path of 23 us printed as
  // "0.000 s" before).
  const auto duration = [](double ns) {
    return ns >= 1e9   ? fmt::format("{:.3f} s", ns * 1e-9)
           : ns >= 1e6 ? fmt::format("{:.3f} ms", ns * 1e-6)
                       : fmt::format("{:.3f} us", ns * 1e-3);
  };
  fmt::print(
      "work {} (sum of task durations), critical path {}\n"
      "gaps between blocks: median {:.0f} ns, mean {:.0f} ns; between tasks in a block: "
      "median {:.0f} ns, mean {:.0f} ns\n",
      duration(static_cast<double>(graph.work_ns())), duration([&] {
        double cp = 0;
        for (const auto& g : graph.iterations) cp += static_cast<double>(g.critical_path_ns);
        return cp;
      }()),
      gaps.block_median, gaps.block_mean, gaps.task_median, gaps.task_mean);
  fmt::print("simulated: scheduler {}, block size {}{}\ncosts (ns): {}\n\n", scheduler, block_size,
             policy == Policy::kPriority ? " (priority replayed in fifo order)" : "",
             costs_to_json(costs));

  // The speed-up baseline is always the 1-processor simulation.
  std::vector<int> runs = procs;
  if (runs.front() != 1) runs.insert(runs.begin(), 1);
  ProgressReporter progress(a.quiet);
  std::map<int, SimResult> results;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    SimConfig c;
    c.policy = policy;
    c.procs = runs[i];
    c.block_size = block_size;
    c.costs = costs;
    c.outside = outside;
    results[runs[i]] = simulate(graph, c, [&](double f) {
      progress.update(fmt::format("simulate {} procs", runs[i]),
                      (static_cast<double>(i) + f) / static_cast<double>(runs.size()));
    });
  }
  progress.finish();

  const SimResult& base = results.at(1);
  const std::size_t iters = graph.iterations.size();
  std::string table = fmt::format("{:>5}  {:>6}", "procs", "kind");
  for (std::size_t k = 0; k < iters; ++k)
    table += fmt::format("  {:>9}", fmt::format("it{} ms", graph.iterations[k].iteration));
  table += fmt::format("  {:>10}  {:>7}  {:>9}  {:>6}  {:>7}  {:>7}\n", "total ms", "speedup",
                       "lock wait", "idle", "outside", "error");
  std::ostringstream csv;
  csv << "kind,scheduler,block_size,procs,iteration,time_s,speedup,busy_share,overhead_share,"
         "lock_wait_share,idle_share,outside_share,tasks,takes,empty_takes,submits,steals,source,"
         "scene\n";
  auto csv_row = [&](const char* kind, int p, const std::string& iteration, double time_s,
                     double speedup, const IterationResult* r, const std::string& source) {
    const double whole = r ? r->time_ns * p : 0;
    auto sh = [&](double v) {
      return whole > 0 ? fmt::format("{:.6f}", v / whole) : std::string();
    };
    csv << fmt::format(
        "{},{},{},{},{},{:.9g},{:.6g},{},{},{},{},{},{},{},{},{},{},{},{}\n", kind, scheduler,
        block_size, p, iteration, time_s, speedup, r ? sh(r->busy_ns) : "",
        r ? sh(r->overhead_ns) : "", r ? sh(r->lock_wait_ns) : "", r ? sh(r->idle_ns) : "",
        r ? sh(r->outside_ns) : "", r ? std::to_string(r->tasks) : "",
        r ? std::to_string(r->takes) : "", r ? std::to_string(r->empty_takes) : "",
        r ? std::to_string(r->submits) : "", r ? std::to_string(r->steals) : "", source, scene);
  };
  for (int p : procs) {
    const SimResult& r = results.at(p);
    const IterationResult t = r.totals();
    table += fmt::format("{:>5}  {:>6}", p, "sim");
    for (const IterationResult& it : r.iterations)
      table += fmt::format("  {:>9.2f}", it.time_ns * 1e-6);
    table += fmt::format("  {:>10.2f}  {:>7.2f}  {:>9}  {:>6}  {:>7}  {:>7}\n", t.time_ns * 1e-6,
                         base.time_ns() / t.time_ns, share(t.lock_wait_ns, t.time_ns * p),
                         share(t.idle_ns, t.time_ns * p), share(t.outside_ns, t.time_ns * p), "");
    for (std::size_t k = 0; k < r.iterations.size(); ++k) {
      const IterationResult& it = r.iterations[k];
      csv_row("simulated", p, std::to_string(it.iteration), it.time_ns * 1e-9,
              base.iterations[k].time_ns / it.time_ns, &it, a.trace);
    }
    csv_row("simulated", p, "all", t.time_ns * 1e-9, base.time_ns() / t.time_ns, &t, a.trace);
    if (p == trace_threads) {  // measured in the traced run: stage start to the last task's end
      double total = 0;
      table += fmt::format("{:>5}  {:>6}", p, "trace");
      for (std::size_t k = 0; k < iters; ++k) {
        const double s = static_cast<double>(graph.iterations[k].measured_span_ns) * 1e-9;
        total += s;
        table += fmt::format("  {:>9.2f}", s * 1e3);
        csv_row("measured-trace", p, std::to_string(graph.iterations[k].iteration), s, 0, nullptr,
                a.trace);
      }
      table += fmt::format("  {:>10.2f}  {:>7}  {:>9}  {:>6}  {:>7}  {:>+6.1f}%\n", total * 1e3, "",
                           "", "", "", 100 * (t.time_ns * 1e-9 - total) / total);
      csv_row("measured-trace", p, "all", total, 0, nullptr, a.trace);
    }
    for (const Measured& m : measured) {
      if (m.threads != p) continue;
      table += fmt::format("{:>5}  {:>6}", p, "real");
      for (std::size_t k = 0; k < iters; ++k)
        table += k < m.refine_s.size() ? fmt::format("  {:>9.2f}", m.refine_s[k] * 1e3)
                                       : fmt::format("  {:>9}", "-");
      table += fmt::format("  {:>10.2f}  {:>7}  {:>9}  {:>6}  {:>7}  {:>+6.1f}%\n", m.total_s * 1e3,
                           "", "", "", "", 100 * (t.time_ns * 1e-9 - m.total_s) / m.total_s);
      if (m.scheduler != scheduler || m.block_size != block_size)
        fmt::print(stderr,
                   "hrad: warning: {} ran {} with block size {}, the simulation {} with {}\n",
                   m.file, m.scheduler, m.block_size, scheduler, block_size);
      for (std::size_t k = 0; k < m.refine_s.size(); ++k)
        csv_row("measured", p, std::to_string(k + 1), m.refine_s[k], 0, nullptr, m.file);
      csv_row("measured", p, "all", m.total_s, 0, nullptr, m.file);
    }
  }
  fmt::print("{}", table);
  fmt::print(
      "\nAll 'sim' rows are simulated (predictions). Measured: 'trace' = the traced run "
      "from the stage's start\nto its last task's end (read from the trace); 'real' = "
      "refine_wall_s of a --measured stats.json.\nerror = (simulated - measured) / measured.\n");
  if (!a.out.empty()) {
    write_file_atomically(a.out, csv.str());
    fmt::print("wrote {}\n", a.out);
  }
  (void)argv;
  return 0;
}

}  // namespace

void register_simulate(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub = app.add_subcommand(
      "simulate",
      "Replay a task trace (hrad solve --set trace=FILE) as a discrete-event simulation on "
      "more processors and predict refinement times and speed-ups.");
  sub->add_option("TRACE", args->trace,
                  "trace file written by hrad solve --set trace=FILE (required but with "
                  "--calibrate-locks)");
  sub->add_option("--procs", args->procs, "comma-separated processor counts")
      ->capture_default_str();
  const std::vector<std::string> unmodelled = unmodelled_schedulers();
  const std::string not_modelled =
      unmodelled.empty() ? "none" : fmt::format("{}", fmt::join(unmodelled, ", "));
  sub->add_option("--scheduler", args->scheduler,
                  fmt::format("policy to replay: {} (priority is replayed in fifo order; not "
                              "modelled: {}) (default: the trace's)",
                              fmt::join(policy_names(), ", "), not_modelled));
  sub->add_option("--block-size", args->block_size,
                  "tasks per take, 0: guided (default: the trace's)")
      ->transform(integer_in(0, kMaxBlockSize));
  sub->add_option("--scale", args->scale,
                  "every time in the trace x this (task durations of another machine: its "
                  "1-thread refinement time / this one's)")
      ->capture_default_str()
      ->check(number_in(1e-6, 1e6));
  sub->add_option("--costs", args->costs,
                  "JSON object of cost model fields (experiments/sim/cost_model.h); repeatable, "
                  "a later file overrides an earlier one");
  sub->add_option("--take-ns", args->take_ns, "central lock held per take, ns")
      ->check(number_in(0, 1e12));
  sub->add_option("--submit-ns", args->submit_ns, "central lock held per submit, ns")
      ->check(number_in(0, 1e12));
  sub->add_option("--steal-ns", args->steal_ns, "per stolen task, ns")->check(number_in(0, 1e12));
  sub->add_option("--overheads", args->overheads,
                  "time outside tasks, from the trace's gaps: 'typical' (block_ns = median gap "
                  "between blocks minus the modelled lock costs, task_ns = 0: predicts an untraced "
                  "run) or 'all' (means of both gaps: the traced run itself, with its tracing "
                  "cost, preemption and page faults)")
      ->capture_default_str();
  sub->add_option("--block-ns", args->block_ns, "per-block time outside the scheduler, ns")
      ->check(number_in(0, 1e12));
  sub->add_option("--task-ns", args->task_ns, "per-task time outside its recorded duration, ns")
      ->check(number_in(0, 1e12));
  sub->add_option("--slowdown", args->slowdown, "task durations x this at 2 or more processors")
      ->check(number_in(1e-3, 1e3));
  sub->add_option(
      "--calibrate", args->calibrate,
      "trace of the same run at 2 threads: slowdown = its summed task durations / TRACE's");
  sub->add_option("--max-task-ns", args->max_task_ns,
                  "cut task durations above this (ns) to it: removes preemptions recorded inside "
                  "tasks on a loaded machine")
      ->transform(integer_in(1, TraceRecord::kBlockStart - 1));
  sub->add_option("--stage-stats", args->stage_stats,
                  "stats.json of the traced 1-thread run: adds each iteration's time outside the "
                  "task loop (reload and load, link compaction, stage start and end), Amdahl over "
                  "outside_serial_share");
  sub->add_option("--measured", args->measured,
                  "stats.json of a real run to compare with (repeatable)");
  sub->add_option("-o,--out", args->out, "write the rows as CSV");
  sub->add_flag("--quiet", args->quiet, "no progress line");
  sub->add_option("--calibrate-locks", args->calibrate_locks,
                  fmt::format("measure the hand-off costs of a lock ({}) at 2 .. --lock-threads "
                              "threads and print them as a --costs object (no TRACE)",
                              fmt::join(calibration_lock_names(), ", ")));
  sub->add_option("--lock-threads", args->lock_threads,
                  "--calibrate-locks: most threads (default: the hardware's)")
      ->transform(integer_in(2, kMaxThreads));
  sub->add_option("--lock-work-ns", args->lock_work_ns,
                  "--calibrate-locks: private work between two acquisitions, ns")
      ->capture_default_str()
      ->check(number_in(0, 1e9));
  sub->callback([args, &ctx] {
    try {
      if (!args->calibrate_locks.empty())
        ctx.status = run_calibrate_locks(*args);
      else if (args->trace.empty())
        throw std::runtime_error("simulate: TRACE is required (or --calibrate-locks LOCK)");
      else
        ctx.status = run_simulate(*args, ctx.argv);
    } catch (const std::exception& e) {
      print_error(e.what());
      ctx.status = 1;
    }
  });
}

}  // namespace hrad::cli

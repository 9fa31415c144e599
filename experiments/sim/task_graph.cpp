#include "experiments/sim/task_graph.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace hrad::sim {

namespace {

constexpr std::uint64_t kSequenceMask = (std::uint64_t{1} << 40) - 1;

std::uint64_t duration_of(const TraceRecord& r) {
  return r.duration_ns & ~TraceRecord::kBlockStart;
}

IterationGraph build_iteration(const std::vector<TraceRecord>& records,
                               const std::vector<std::size_t>& members, int iteration,
                               const std::string& what) {
  IterationGraph g;
  g.iteration = iteration;
  std::unordered_map<std::uint64_t, std::size_t> by_id;
  by_id.reserve(members.size() * 2);
  std::vector<std::size_t> roots;
  for (std::size_t m : members) {
    const TraceRecord& r = records[m];
    if (!by_id.emplace(r.id, m).second)
      throw std::runtime_error(
          fmt::format("{}: iteration {}: task id {:#x} appears twice", what, iteration, r.id));
    if (is_initial_task(r.id)) roots.push_back(m);
    g.measured_span_ns = std::max(g.measured_span_ns, r.start_ns + duration_of(r));
    g.first_start_ns = by_id.size() == 1 ? r.start_ns : std::min(g.first_start_ns, r.start_ns);
    if (r.duration_ns & TraceRecord::kBlockStart) ++g.blocks;
  }
  if (roots.empty())
    throw std::runtime_error(
        fmt::format("{}: iteration {}: no initial task (ids without a worker)", what, iteration));
  std::sort(roots.begin(), roots.end(), [&](std::size_t a, std::size_t b) {
    return (records[a].id & kSequenceMask) < (records[b].id & kSequenceMask);
  });

  // Breadth-first renumbering: the queue order is the new index order, so the children
  // a task appends are consecutive.
  std::vector<std::size_t> order = roots;
  order.reserve(members.size());
  // Record index -> new index; also catches a task created twice.
  std::unordered_map<std::size_t, std::uint32_t> new_index;
  new_index.reserve(members.size() * 2);
  for (std::size_t i = 0; i < roots.size(); ++i)
    new_index.emplace(roots[i], static_cast<std::uint32_t>(i));
  g.tasks.resize(members.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const TraceRecord& r = records[order[k]];
    SimTask& t = g.tasks[k];
    t.duration_ns = duration_of(r);
    t.first_child = static_cast<std::uint32_t>(order.size());
    t.children = r.children;
    for (std::uint32_t c = 0; c < r.children; ++c) {
      const std::uint64_t cid = r.first_child + c;
      const auto it = by_id.find(cid);
      if (it == by_id.end())
        throw std::runtime_error(fmt::format(
            "{}: iteration {}: task {:#x} created task {:#x}, which is not in the trace", what,
            iteration, r.id, cid));
      if (!new_index.emplace(it->second, static_cast<std::uint32_t>(order.size())).second)
        throw std::runtime_error(
            fmt::format("{}: iteration {}: task {:#x} is created twice (or is an initial task)",
                        what, iteration, cid));
      order.push_back(it->second);
    }
  }
  if (order.size() != members.size())
    throw std::runtime_error(
        fmt::format("{}: iteration {}: {} of {} tasks are not reachable from the initial tasks",
                    what, iteration, members.size() - order.size(), members.size()));
  g.roots = static_cast<std::uint32_t>(roots.size());

  // Children have larger indices than their parent: one backward pass.
  std::vector<std::uint64_t> path(g.tasks.size(), 0);
  for (std::size_t k = g.tasks.size(); k-- > 0;) {
    const SimTask& t = g.tasks[k];
    std::uint64_t longest = 0;
    for (std::uint32_t c = 0; c < t.children; ++c)
      longest = std::max(longest, path[t.first_child + c]);
    path[k] = t.duration_ns + longest;
    g.work_ns += t.duration_ns;
  }
  for (std::uint32_t i = 0; i < g.roots; ++i)
    g.critical_path_ns = std::max(g.critical_path_ns, path[i]);
  return g;
}

}  // namespace

std::uint64_t TaskGraph::tasks() const {
  std::uint64_t n = 0;
  for (const IterationGraph& g : iterations) n += g.tasks.size();
  return n;
}

std::uint64_t TaskGraph::work_ns() const {
  std::uint64_t n = 0;
  for (const IterationGraph& g : iterations) n += g.work_ns;
  return n;
}

TaskGraph build_task_graph(const std::vector<TraceRecord>& records, const std::string& what) {
  std::map<int, std::vector<std::size_t>> by_iteration;
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (records[i].iteration == 0)
      throw std::runtime_error(
          fmt::format("{}: record {}: iteration 0 (iterations are 1-based)", what, i));
    by_iteration[records[i].iteration].push_back(i);
  }
  TaskGraph graph;
  for (const auto& [iteration, members] : by_iteration)
    graph.iterations.push_back(build_iteration(records, members, iteration, what));
  return graph;
}

GapStats gap_stats(const std::vector<TraceRecord>& records) {
  std::map<std::pair<int, int>, std::vector<const TraceRecord*>> lanes;
  for (const TraceRecord& r : records) lanes[{r.iteration, r.worker}].push_back(&r);
  std::vector<double> block_gaps, task_gaps;
  for (auto& [key, lane] : lanes) {
    std::sort(lane.begin(), lane.end(),
              [](const TraceRecord* a, const TraceRecord* b) { return a->start_ns < b->start_ns; });
    for (std::size_t i = 1; i < lane.size(); ++i) {
      const std::uint64_t prev_end = lane[i - 1]->start_ns + duration_of(*lane[i - 1]);
      const double gap =
          lane[i]->start_ns > prev_end ? static_cast<double>(lane[i]->start_ns - prev_end) : 0.0;
      ((lane[i]->duration_ns & TraceRecord::kBlockStart) ? block_gaps : task_gaps).push_back(gap);
    }
  }
  auto median = [](std::vector<double>& v) {
    if (v.empty()) return 0.0;
    auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  GapStats g;
  g.block_mean = mean(block_gaps);
  g.task_mean = mean(task_gaps);
  g.block_median = median(block_gaps);
  g.task_median = median(task_gaps);
  return g;
}

double median_block_gap_ns(const std::vector<TraceRecord>& records) {
  return gap_stats(records).block_median;
}

}  // namespace hrad::sim

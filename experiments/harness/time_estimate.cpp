#include "experiments/harness/time_estimate.h"

#include "core/base/clock.h"
#include "core/config/options_io.h"
#include "core/scene/scene_loader.h"
#include "core/solver/solver.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace hrad::experiment {

namespace {

// What makes points one group: the scene and every option but eps and those that only
// say how a run goes in parallel (or what it records on the side).
std::string group_key(const SweepPoint& p) {
  nlohmann::json j = options_to_json(p.options);
  for (const char* k : {"eps", "threads", "scheduler", "block_size", "pin", "placement",
                        "pool_order", "seed", "trace"})
    j.erase(k);
  for (auto it = j.begin(); it != j.end();)
    it = it.key().rfind("scheduler.", 0) == 0 ? j.erase(it) : std::next(it);
  return p.scene + "\n" + j.dump();
}

// Pilots shorter than this are too noisy to give a rate.
constexpr double kShortestPilot = 0.01;
constexpr double kDefaultBeta = 0.8;

}  // namespace

double scaled_estimate(double near, double far, double eps_near, double eps, int threads,
                       int cores) {
  double beta = kDefaultBeta;
  if (far >= kShortestPilot)
    beta = std::clamp(std::log(near / far) / std::log(kPilotFar / kPilotNear), 0.0, 1.5);
  const double one_thread = near * std::pow(eps_near / eps, beta);
  const int used = std::max(1, std::min(threads, std::max(cores, 1)));
  return used > 1 ? one_thread / (used * kParallelEfficiency) : one_thread;
}

std::string rough_duration(double seconds) {
  if (!(seconds >= 0)) return "unknown";
  if (seconds < 1) return "under a second";
  if (seconds < 60)
    return fmt::format("about {:.0f} s",
                       seconds < 10 ? std::ceil(seconds) : std::round(seconds / 5) * 5);
  if (seconds < 3600) {
    const double m = std::round(seconds / 60);
    return fmt::format("about {:.0f} min", std::max(1.0, m));
  }
  return fmt::format("about {:.1f} h", seconds / 3600);
}

TimeEstimate estimate_time(const ExperimentConfig& config, const std::vector<SweepPoint>& points,
                           int cores, std::FILE* log, bool quiet) {
  TimeEstimate est;
  est.point_seconds.assign(points.size(), 0.0);
  // Each group's points and smallest eps, in the points' order.
  std::map<std::string, std::vector<std::size_t>> groups;
  std::vector<std::string> order;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string key = group_key(points[i]);
    if (groups.find(key) == groups.end()) order.push_back(key);
    groups[key].push_back(i);
  }
  const auto start = Clock::now();
  std::string loaded;
  SceneLoadOptions loaded_with;
  std::optional<Scene> scene;
  for (const std::string& key : order) {
    const std::vector<std::size_t>& members = groups[key];
    const SweepPoint& first = points[members.front()];
    double eps = first.options.eps;
    for (std::size_t i : members) eps = std::min(eps, points[i].options.eps);
    const SceneLoadOptions load = scene_load_options(first.options);
    if (!scene || loaded != first.scene || !(loaded_with == load)) {
      scene.reset();
      scene = load_scene(first.scene, load);
      loaded = first.scene;
      loaded_with = load;
    }
    const auto pilot = [&](double factor) {
      SolverOptions o = first.options;
      o.threads = 1;
      o.eps = std::min(1.0, factor * eps);
      o.trace.clear();
      const auto t0 = Clock::now();
      Solver solver(*scene, o);
      (void)solver.run();
      return seconds_since(t0);
    };
    const double far = pilot(kPilotFar);
    const double near = pilot(kPilotNear);
    est.pilots += 2;
    const double eps_near = std::min(1.0, kPilotNear * eps);
    for (std::size_t i : members)
      est.point_seconds[i] = scaled_estimate(near, far, eps_near, points[i].options.eps,
                                             points[i].options.threads, cores);
    if (!quiet)
      fmt::print(log, "  pilot {}: eps {:g} {:.3g} s, eps {:g} {:.3g} s\n", first.scene,
                 std::min(1.0, kPilotFar * eps), far, eps_near, near);
  }
  est.pilot_seconds = seconds_since(start);
  for (double s : est.point_seconds) est.total_seconds += s * config.repetitions;
  return est;
}

}  // namespace hrad::experiment

// The scheduler registry: name -> factory, filled by each scheduler's file.
#include "schedulers/scheduler.h"

#include <fmt/format.h>

#include <stdexcept>

namespace hrad {

namespace {
struct Entry {
  SchedulerFactory factory;
  std::vector<ParamSpec> params;
};
std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> r;
  return r;
}
}  // namespace

bool register_scheduler(const std::string& name, SchedulerFactory factory,
                        std::vector<ParamSpec> params) {
  registry()[name] = {std::move(factory), std::move(params)};
  return true;
}

std::span<const ParamSpec> scheduler_params(const std::string& name) {
  check_scheduler_name(name);
  return registry().find(name)->second.params;
}

std::vector<std::string> scheduler_names() {
  std::vector<std::string> names;
  for (const auto& [name, f] : registry()) names.push_back(name);
  return names;
}

void check_scheduler_name(const std::string& name) {
  if (!registry().contains(name))
    throw std::invalid_argument(fmt::format("unknown scheduler '{}' (known: {})", name,
                                            fmt::join(scheduler_names(), ", ")));
}

std::unique_ptr<IScheduler> make_scheduler(const std::string& name, const SchedulerConfig& config) {
  check_scheduler_name(name);
  const auto it = registry().find(name);
  if (config.threads < 1 || config.block_size < 0)
    throw std::invalid_argument("scheduler needs threads >= 1 and block_size >= 0 (0: guided)");
  const PluginParams params("scheduler " + name, it->second.params, config.params);
  auto scheduler = it->second.factory(config, params);
  params.report_unused();
  return scheduler;
}

}  // namespace hrad

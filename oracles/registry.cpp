// The oracle registry: name -> factory, filled by each oracle's file.
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

namespace hrad {

namespace {
struct Entry {
  OracleFactory factory;
  std::vector<ParamSpec> params;
};
std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> r;
  return r;
}
}  // namespace

bool register_oracle(const std::string& name, OracleFactory factory,
                     std::vector<ParamSpec> params) {
  registry()[name] = {std::move(factory), std::move(params)};
  return true;
}

std::span<const ParamSpec> oracle_params(const std::string& name) {
  check_oracle_name(name);
  return registry().find(name)->second.params;
}

std::vector<std::string> oracle_names() {
  std::vector<std::string> names;
  for (const auto& [name, f] : registry()) names.push_back(name);
  return names;
}

void check_oracle_name(const std::string& name) {
  if (!registry().contains(name))
    throw std::invalid_argument(
        fmt::format("unknown oracle '{}' (known: {})", name, fmt::join(oracle_names(), ", ")));
}

std::unique_ptr<IOracle> make_oracle(const std::string& name, const ParamValues& values) {
  check_oracle_name(name);
  const Entry& e = registry().find(name)->second;
  const PluginParams params("oracle " + name, e.params, values);
  auto oracle = e.factory(params);
  params.report_unused();
  return oracle;
}

}  // namespace hrad

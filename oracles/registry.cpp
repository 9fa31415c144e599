// The oracle registry: name -> factory, filled by each oracle's file.
#include "core/hierarchy/element.h"
#include "oracles/oracle.h"

#include <fmt/format.h>

#include <map>
#include <stdexcept>

namespace hrad {

namespace {
std::map<std::string, OracleFactory>& registry() {
  static std::map<std::string, OracleFactory> r;
  return r;
}
}  // namespace

bool register_oracle(const std::string& name, OracleFactory factory) {
  registry()[name] = std::move(factory);
  return true;
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

std::unique_ptr<IOracle> make_oracle(const std::string& name) {
  check_oracle_name(name);
  return registry().find(name)->second();
}

}  // namespace hrad

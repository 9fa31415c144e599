// The oracle registry: name -> factory, filled by each oracle's file.
#include "core/element.h"
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

std::unique_ptr<IOracle> make_oracle(const std::string& name) {
  const auto it = registry().find(name);
  if (it == registry().end())
    throw std::invalid_argument(
        fmt::format("unknown oracle '{}' (known: {})", name, fmt::join(oracle_names(), ", ")));
  return it->second();
}


}  // namespace hrad

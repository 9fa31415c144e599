// libFuzzer entry for the JSON configuration readers: the input is read as `hrad solve
// --config` reads its file (core/base/json_input.h, then apply_options_json and
// validate_options) and as `hrad experiment` reads a configuration
// (parse_experiment_config). std::invalid_argument, with its file and what is wrong, is
// the expected outcome for bad input; anything else (a crash, a sanitizer report, a
// nlohmann exception escaping, a hang) is a bug. Nesting was what crashed: 100,000
// brackets overflowed the stack where a value was echoed.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/base/json_input.h"
#include "core/config/options_io.h"
#include "experiments/harness/experiment_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto j = hrad::parse_json_document<nlohmann::json>(text, "fuzz.json", true);
    hrad::SolverOptions o;
    hrad::apply_options_json(o, j, "fuzz.json");
    hrad::validate_options(o);
  } catch (const std::invalid_argument&) {
  }
  try {
    const auto j = hrad::parse_json_document<nlohmann::ordered_json>(text, "fuzz.json", true);
    (void)hrad::experiment::parse_experiment_config(j, "fuzz.json");
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

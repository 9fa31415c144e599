// libFuzzer entry for the probe-file reader (parse_probes: "x y z nx ny nz" lines,
// comments, blank lines). An InputError naming the line is the expected outcome for
// bad input; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/base/input_error.h"
#include "core/scene/probes.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)hrad::parse_probes(std::string(reinterpret_cast<const char*>(data), size), "fuzz.txt");
  } catch (const hrad::InputError&) {
  }
  return 0;
}

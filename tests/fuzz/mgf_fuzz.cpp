// libFuzzer target for the MGF reader: any input must either parse or throw
// InputError; any other exception, crash, hang or huge allocation is a bug.
// Limits are set lower than the defaults so that each input stays fast; `i`
// includes resolve against the current directory (the seed corpus uses none).
#include "core/base/input_error.h"
#include "core/scene/mgf/mgf_reader.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hrad::MgfOptions options;
  options.segments = 8;
  options.max_array = 1000;
  options.max_repeat = 1000;
  options.max_work = 20000;
  try {
    hrad::parse_mgf(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.mgf",
                    options);
  } catch (const hrad::InputError&) {
  }
  return 0;
}

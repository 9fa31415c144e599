// libFuzzer entry for the OBJ/MTL reader. The input is OBJ text, optionally followed
// by a NUL byte and MTL text (further NULs belong to the MTL and make it invalid).
// An InputError is the expected outcome for bad input; anything else (a crash, a
// sanitizer report, another exception, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/base/input_error.h"
#include "core/scene/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = in.find('\0');
  const std::string_view obj = in.substr(0, nul);
  const std::string_view mtl =
      nul == std::string_view::npos ? std::string_view() : in.substr(nul + 1);
  try {
    (void)hrad::parse_obj(obj, mtl, "fuzz.obj");
  } catch (const hrad::InputError&) {
  }
  return 0;
}

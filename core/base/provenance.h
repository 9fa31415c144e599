// How this hrad was built, for the records a run leaves (the "hrad" blocks of
// stats.json and manifest.json): one place that asks the compiler and CMake.
#pragma once

namespace hrad {

struct BuildInfo {
  const char* compiler;    ///< "gcc 12.2.0", "clang 14.0.6": what compiled hrad
  const char* build_type;  ///< CMAKE_BUILD_TYPE ("unknown" where CMake did not say)
  const char* cxx_flags;   ///< that build type's C++ flags ("unknown" where CMake did not say)
};

[[nodiscard]] BuildInfo build_info();

}  // namespace hrad

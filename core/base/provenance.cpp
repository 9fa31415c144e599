#include "core/base/provenance.h"

// core/CMakeLists.txt defines these for this file only, so that a change of flags
// recompiles nothing else.
#ifndef HRAD_BUILD_TYPE
#define HRAD_BUILD_TYPE "unknown"
#endif
#ifndef HRAD_CXX_FLAGS
#define HRAD_CXX_FLAGS "unknown"
#endif

namespace hrad {

BuildInfo build_info() {
#ifdef __clang__
  constexpr const char* compiler = "clang " __clang_version__;
#else
  constexpr const char* compiler = "gcc " __VERSION__;
#endif
  return {compiler, HRAD_BUILD_TYPE, HRAD_CXX_FLAGS};
}

}  // namespace hrad

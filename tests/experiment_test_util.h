// Helpers shared by the experiment harness tests: a scratch folder under the system's
// temporary directory, and the manifest inputs of a test run.
#pragma once

#include "experiments/harness/manifest.h"

#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <string>

namespace hrad::test {

/// A folder named `name`-PID in the temporary directory (the pid keeps concurrent test
/// runs from other build folders apart), emptied on construction (and created when
/// `create`) and removed on destruction.
struct ScratchFolder {
  std::filesystem::path path;
  explicit ScratchFolder(const char* name, bool create = false)
      : path(std::filesystem::temp_directory_path() /
             (name + std::string("-") + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    if (create) std::filesystem::create_directories(path);
  }
  ~ScratchFolder() { std::filesystem::remove_all(path); }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

/// Manifest inputs for running config `c` (read from `config_file`) with `points` points.
inline experiment::ManifestInputs manifest_inputs_for(const experiment::ExperimentConfig& c,
                                                      std::size_t points,
                                                      const std::string& config_file) {
  experiment::ManifestInputs in;
  in.config = c;
  in.config_file = config_file;
  in.command_line = {"hrad", "experiment", config_file};
  in.version = "test";
  in.git_revision = "abc";
  in.points = static_cast<int>(points);
  return in;
}

}  // namespace hrad::test

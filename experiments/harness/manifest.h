// manifest.json: everything needed to tell how a result folder was made, written
// beside runs.csv when an experiment starts ("status": "running") and again when it
// ends ("complete" or "failed"). Keys:
//
//   experiment   name, description, config_file, quick, sets (the --set arguments),
//                config (the resolved configuration: --quick and --set applied; resume
//                requires it unchanged), points, repetitions, runs
//   hrad         version, git_revision, compiler, build_type, cxx_flags
//   command_line the arguments
//   machine      hostname, os (uname), cpu (hwloc's description, CPU model tidied),
//                pus, memory_bytes
//   topology     as `hrad topology`: packages, numa_nodes, cores, pus, description,
//                synthetic, nodes [{os_index, package, cores, pus, cpus, memory_bytes}]
//   environment  every OMP_*, GOMP_*, KMP_*, HRAD_* and HWLOC_* variable that is set
//   started_at, finished_at (ISO 8601 local time with offset), status, runs_done,
//   columns      {runs: [...], iterations: [...]} the CSV headers
#pragma once

#include "experiments/harness/experiment_config.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace hrad::experiment {

struct ManifestInputs {
  ExperimentConfig config;  ///< resolved
  std::string config_file;
  bool quick = false;
  std::vector<std::string> sets;
  std::vector<std::string> command_line;
  std::string version, git_revision;
  int points = 0;
};

/// This host as the result rows describe it: its name, CPU model (tidied; "" when
/// unknown) and physical cores (0 when unknown), from the same sources as the
/// manifest's `machine` and `topology`. Under a synthetic topology (HWLOC_SYNTHETIC,
/// HWLOC_XMLFILE) model and cores are unknown: that topology is not this host's.
struct HostInfo {
  std::string hostname, cpu_model;
  int cores = 0;
};
[[nodiscard]] HostInfo this_host();

/// The 1-minute load average now; NaN when the system does not tell.
[[nodiscard]] double load_average_1min();

/// A new manifest (status "running", started now).
[[nodiscard]] nlohmann::ordered_json make_manifest(const ManifestInputs& in);

/// Every environment variable starting with OMP_, GOMP_, KMP_, HRAD_ or HWLOC_.
[[nodiscard]] nlohmann::ordered_json relevant_environment();

/// Local time now, ISO 8601 with UTC offset ("2026-11-22T06:01:02+0000").
[[nodiscard]] std::string now_iso8601();

/// "20261122-060102" for folder names.
[[nodiscard]] std::string now_stamp();

/// Writes `dir`/manifest.json atomically.
void write_manifest(const std::filesystem::path& dir, const nlohmann::ordered_json& manifest);

/// Reads `dir`/manifest.json. Throws std::runtime_error naming the file when it is
/// missing or not JSON.
[[nodiscard]] nlohmann::ordered_json read_manifest(const std::filesystem::path& dir);

}  // namespace hrad::experiment

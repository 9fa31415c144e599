#include "experiments/harness/manifest.h"

#include "core/base/atomic_file.h"
#include "core/base/input_file.h"
#include "core/base/json_input.h"
#include "core/base/provenance.h"
#include "core/parallel/topology.h"
#include "experiments/harness/core_share.h"
#include "experiments/harness/run_rows.h"

#include <fmt/format.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace hrad::experiment {
namespace {

using ojson = nlohmann::ordered_json;

std::string local_time(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::localtime_r(&now, &tm);
  char buf[64];
  return std::strftime(buf, sizeof buf, format, &tm) > 0 ? buf : "";
}

ojson topology_json(std::string& cpu) {
  try {
    const TopologyInfo t = discover_topology();
    cpu = t.description;
    ojson nodes = ojson::array();
    for (const NumaNodeInfo& n : t.nodes)
      nodes.push_back({{"os_index", n.os_index},
                       {"package", n.package},
                       {"cores", n.cores},
                       {"pus", n.pus},
                       {"cpus", n.cpus},
                       {"memory_bytes", n.memory_bytes}});
    return {{"packages", t.packages}, {"numa_nodes", t.numa_nodes},   {"cores", t.cores},
            {"pus", t.pus},           {"description", t.description}, {"synthetic", t.synthetic},
            {"nodes", nodes}};
  } catch (const std::exception& e) {
    return {{"error", e.what()}};
  }
}

std::string host_name() {
  char host[256] = {};
  return ::gethostname(host, sizeof host - 1) == 0 ? host : "unknown";
}

ojson machine_json(const std::string& cpu) {
  ojson m = ojson::object();
  m["hostname"] = host_name();
  struct utsname u {};
  m["os"] = ::uname(&u) == 0 ? fmt::format("{} {} {}", u.sysname, u.release, u.machine)
                             : std::string("unknown");
  m["cpu"] = cpu;
  m["pus_online"] = ::sysconf(_SC_NPROCESSORS_ONLN);
  m["cpus_allowed"] = allowed_cpus().size();  // this process's affinity
  // The load when the experiment started: other work on the machine slows its runs.
  double load[3] = {0, 0, 0};
  if (::getloadavg(load, 3) == 3) m["load_average"] = {load[0], load[1], load[2]};
  m["memory_bytes"] = static_cast<std::uint64_t>(::sysconf(_SC_PHYS_PAGES)) *
                      static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
  return m;
}

}  // namespace

HostInfo this_host() {
  HostInfo h;
  h.hostname = host_name();
  try {
    const TopologyInfo t = discover_topology();
    if (!t.synthetic) {  // a synthetic topology is not this host's
      h.cpu_model = t.cpu_model;
      h.cores = t.cores;
    }
  } catch (const std::exception&) {
    // hwloc failed: model and cores unknown
  }
  return h;
}

double load_average_1min() {
  double load[1] = {0};
  return ::getloadavg(load, 1) == 1 ? load[0] : std::numeric_limits<double>::quiet_NaN();
}

std::string now_iso8601() { return local_time("%Y-%m-%dT%H:%M:%S%z"); }
std::string now_stamp() { return local_time("%Y%m%d-%H%M%S"); }

ojson relevant_environment() {
  ojson env = ojson::object();
  std::vector<std::string> vars;
  for (char** e = environ; e && *e; ++e) vars.emplace_back(*e);
  std::sort(vars.begin(), vars.end());
  for (const std::string& v : vars) {
    const auto eq = v.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = v.substr(0, eq);
    for (const char* prefix : {"OMP_", "GOMP_", "KMP_", "HRAD_", "HWLOC_"})
      if (key.rfind(prefix, 0) == 0) env[key] = v.substr(eq + 1);
  }
  return env;
}

ojson make_manifest(const ManifestInputs& in) {
  const ExperimentConfig& c = in.config;
  std::string cpu;
  const ojson topology = topology_json(cpu);
  ojson m = ojson::object();
  m["experiment"] = {{"name", c.name},
                     {"description", c.description},
                     {"config_file", in.config_file},
                     {"quick", in.quick},
                     {"sets", in.sets},
                     {"config", experiment_config_to_json(c)},
                     {"points", in.points},
                     {"repetitions", c.repetitions},
                     {"runs", in.points * c.repetitions}};
  const BuildInfo build = build_info();
  m["hrad"] = {{"version", in.version},
               {"git_revision", in.git_revision},
               {"compiler", build.compiler},
               {"build_type", build.build_type},
               {"cxx_flags", build.cxx_flags}};
  m["command_line"] = in.command_line;
  m["machine"] = machine_json(cpu);
  m["topology"] = topology;
  m["environment"] = relevant_environment();
  m["started_at"] = now_iso8601();
  m["finished_at"] = nullptr;
  m["status"] = "running";
  m["runs_done"] = 0;
  m["columns"] = {{"runs", run_columns()}, {"iterations", iteration_columns()}};
  return m;
}

void write_manifest(const std::filesystem::path& dir, const ojson& manifest) {
  write_file_atomically(dir / "manifest.json", manifest.dump(2) + "\n");
}

ojson read_manifest(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "manifest.json";
  check_input_file(path, "the manifest");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path.string()));
  std::stringstream s;
  s << in.rdbuf();
  try {
    return parse_json_document<ojson>(s.str(), path.string(), /*comments=*/false);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
}

}  // namespace hrad::experiment

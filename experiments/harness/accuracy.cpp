#include "experiments/harness/accuracy.h"

#include "core/base/atomic_file.h"
#include "core/base/clock.h"
#include "core/base/percent.h"
#include "core/reference/path_tracer.h"
#include "core/solver/solver.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <stdexcept>

namespace hrad::experiment {
namespace {

namespace fs = std::filesystem;

std::string g9(double v) { return fmt::format("{:.9g}", v); }

std::string reference_csv(const std::vector<Probe>& probes, const ReferenceResult& r) {
  std::string out = "x,y,z,nx,ny,nz,E_r,E_g,E_b,SE_r,SE_g,SE_b,samples\n";
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Probe& p = probes[i];
    const ProbeEstimate& e = r.probes[i];
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", g9(p.p.x()), g9(p.p.y()),
                       g9(p.p.z()), g9(p.n.x()), g9(p.n.y()), g9(p.n.z()), g9(e.irradiance[0]),
                       g9(e.irradiance[1]), g9(e.irradiance[2]), g9(e.std_error[0]),
                       g9(e.std_error[1]), g9(e.std_error[2]), e.samples);
  }
  return out;
}

}  // namespace

std::string reference_file_name(const std::string& scene) {
  std::string s = scene;
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) c = '_';
  return "reference-" + s + ".csv";
}

std::vector<Probe> accuracy_probes(const AccuracySpec& a, const std::string& scene) {
  const fs::path file = accuracy_probe_file(a, scene);
  if (file.empty())
    throw std::invalid_argument(
        fmt::format("accuracy.probes names no probe file for scene '{}'", scene));
  std::vector<Probe> probes = read_probes(file.string());
  if (probes.empty())
    throw std::invalid_argument(fmt::format("{}: no probes in the file", file.string()));
  return probes;
}

SceneReference scene_reference(const fs::path& dir, const std::string& scene_spec,
                               const Scene& scene, const AccuracySpec& a, int threads,
                               std::FILE* log, bool quiet) {
  SceneReference ref;
  ref.probes = accuracy_probes(a, scene_spec);
  const fs::path csv = dir / reference_file_name(scene_spec);
  std::error_code ec;
  if (fs::is_regular_file(csv, ec)) {
    ref.table = read_probe_table(csv);
    // Same probe set as the file names now (throws naming both otherwise).
    ProbeTable mine{"accuracy.probes", ref.probes, ref.table.irradiance, {}};
    (void)compare_probes(mine, ref.table);
    return ref;
  }
  PathTracerOptions o;
  o.rel_error = a.reference_rel_error;
  o.max_samples = static_cast<std::uint64_t>(a.reference_max_samples);
  o.threads = std::max(1, threads);
  if (!quiet)
    fmt::print(log,
               "hrad experiment: path-traced reference for {} ({} probes, {} relative "
               "error)...\n",
               scene_spec, ref.probes.size(), percent_text(a.reference_rel_error));
  std::fflush(log);
  const PathTracer tracer(scene);
  const ReferenceResult r = tracer.estimate(ref.probes, o);
  std::vector<std::size_t> unconverged;
  std::uint64_t samples = 0;
  for (std::size_t i = 0; i < r.probes.size(); ++i) {
    samples += r.probes[i].samples;
    if (!r.probes[i].converged) unconverged.push_back(i);
  }
  if (!unconverged.empty())
    fmt::print(log,
               "hrad: warning: {}: {} of {} reference probes missed the {} relative error "
               "target\n",
               scene_spec, unconverged.size(), r.probes.size(),
               percent_text(a.reference_rel_error));
  write_file_atomically(csv, reference_csv(ref.probes, r));
  nlohmann::ordered_json j;
  j["scene"] = scene_spec;
  j["probes_file"] = accuracy_probe_file(a, scene_spec).string();
  j["rel_error"] = a.reference_rel_error;
  j["max_samples"] = a.reference_max_samples;
  j["threads"] = o.threads;
  j["floor"] = {r.floor[0], r.floor[1], r.floor[2]};
  j["samples_total"] = samples;
  j["rays_cast"] = r.rays;
  j["rounds"] = r.rounds;
  j["wall_s"] = r.seconds;
  j["converged"] = unconverged.empty();
  j["unconverged_probes"] = unconverged;
  fs::path js = csv;
  js.replace_extension(".json");
  write_file_atomically(js, j.dump(2) + "\n");
  ref.table = read_probe_table(csv);
  ref.computed = true;
  ref.seconds = r.seconds;
  if (!quiet)
    fmt::print(log, "hrad experiment: reference for {}: {:.2f} s, {} paths -> {}\n", scene_spec,
               r.seconds, samples, csv.filename().string());
  return ref;
}

AccuracyFigures measure_accuracy(const Solver& solver, const SceneReference& ref,
                                 const AccuracySpec& a) {
  const auto t0 = Clock::now();
  std::vector<Rgb> e = solver.probe_irradiance(ref.probes);
  AccuracyFigures f;
  f.probe_s = seconds_since(t0);
  const ProbeTable result{"run", ref.probes, std::move(e), {}};
  const ProbeComparison c = compare_probes(result, ref.table, a.floor);
  f.mean = c.mean;
  f.max = c.max;
  f.rms = c.rms;
  return f;
}

}  // namespace hrad::experiment

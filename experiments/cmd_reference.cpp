// `hrad reference SCENE --probes FILE --out DIR`: Monte Carlo path-traced irradiance at
// probe points (core/reference/path_tracer.h), the independent reference for `hrad solve`.
//
// Writes into DIR (created only after the scene and the probes have loaded):
//   probes.csv      x,y,z,nx,ny,nz,E_r,E_g,E_b as `solve` writes it, then SE_r,SE_g,SE_b
//                   (standard error of E per channel) and samples (paths traced);
//   reference.json  options, floor, per-probe samples and convergence, time, rays.
// Both atomically. Exit 1 on bad input; probes that miss the target are listed on stderr
// and in reference.json, but the run still succeeds (status 0).
#include "core/base/atomic_file.h"
#include "core/base/interrupt.h"
#include "core/base/percent.h"
#include "core/base/progress.h"
#include "core/config/options_io.h"
#include "core/output/stats_json.h"
#include "core/reference/path_tracer.h"
#include "core/scene/probes.h"
#include "core/scene/scene_loader.h"
#include "experiments/commands.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <filesystem>
#include <limits>
#include <memory>

namespace hrad::cli {
namespace {

namespace fs = std::filesystem;

struct ReferenceArgs {
  std::string scene, probes, out;
  std::size_t random_probes = 0;
  PathTracerOptions options;
  /// The scene's `sides` and `segments` keys, as `hrad solve` takes them (the reference
  /// must trace the scene the solver solves).
  SolverOptions scene_keys;
  std::string sides = "auto";           ///< --sides as given, applied to scene_keys as the key is
  std::string emitter_sides = "front";  ///< --emitter-sides as given, likewise
  bool quiet = false;
};

std::string reference_csv(const std::vector<Probe>& probes, const ReferenceResult& r) {
  std::string out = "x,y,z,nx,ny,nz,E_r,E_g,E_b,SE_r,SE_g,SE_b,samples\n";
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3& p = probes[i].p;
    const Vec3& n = probes[i].n;
    const Rgb& e = r.probes[i].irradiance;
    const Rgb& s = r.probes[i].std_error;
    out += fmt::format(
        "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
        "{:.9g},{}\n",
        p[0], p[1], p[2], n[0], n[1], n[2], e[0], e[1], e[2], s[0], s[1], s[2],
        r.probes[i].samples);
  }
  return out;
}

int run_reference(ReferenceArgs& a, const CommandContext& ctx) {
  Scene scene;
  std::vector<Probe> probes;
  std::unique_ptr<PathTracer> tracer;
  try {
    if (a.probes.empty() && a.random_probes == 0)
      throw std::invalid_argument("give the probe points: --probes FILE or --random-probes N");
    apply_option_value(a.scene_keys, "sides", a.sides, "--sides");
    apply_option_value(a.scene_keys, "emitter_sides", a.emitter_sides, "--emitter-sides");
    validate_options(a.scene_keys);
    scene = load_scene(a.scene, scene_load_options(a.scene_keys));
    if (a.random_probes > 0) {
      probes = random_surface_probes(scene, a.random_probes, a.options.seed);
    } else {
      probes = read_probes(a.probes);
      if (probes.empty()) throw std::invalid_argument(fmt::format("{}: no probes", a.probes));
    }
    for (const std::string& w : scene.warnings) fmt::print(stderr, "hrad: warning: {}\n", w);
    tracer = std::make_unique<PathTracer>(scene);
    // Option ranges, before anything is created (estimate() checks them too).
    PathTracerOptions check = a.options;
    if (!(check.rel_error > 0)) throw std::invalid_argument("--rel-error must be > 0");
    if (check.threads < 1) throw std::invalid_argument("--threads must be >= 1");
    if (check.max_samples < static_cast<std::uint64_t>(check.batch_size) * check.min_batches)
      throw std::invalid_argument(
          fmt::format("--max-samples must be >= {}", check.batch_size * check.min_batches));
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }

  const fs::path out(a.out);
  bool created = false;
  if (!make_output_folder(out, created)) return 1;
  // An earlier reference's results in the folder go first (as for solve).
  for (const char* name : {"reference.json", "probes.csv", "probes.txt"}) {
    std::error_code ec;
    const bool input = !a.probes.empty() && fs::equivalent(a.probes, out / name, ec);
    if (!input) fs::remove(out / name, ec);
  }

  try {
    ProgressReporter progress(a.quiet);
    const ReferenceResult r = tracer->estimate(probes, a.options, progress.callback());
    progress.finish();
    if (a.random_probes > 0)
      write_file_atomically(
          out / "probes.txt",
          probes_text(probes, fmt::format("{} random surface probes of {}, seed {}", probes.size(),
                                          a.scene, a.options.seed)));
    write_file_atomically(out / "probes.csv", reference_csv(probes, r));

    nlohmann::json unconverged = nlohmann::json::array();
    nlohmann::json per_probe = nlohmann::json::array();
    std::uint64_t total = 0, truncated = 0;
    std::size_t truncated_probes = 0;
    for (std::size_t i = 0; i < probes.size(); ++i) {
      const ProbeEstimate& e = r.probes[i];
      total += e.samples;
      truncated += e.truncated;
      truncated_probes += e.truncated > 0;
      if (!e.converged) unconverged.push_back(i);
      const Rgb rel = e.std_error / e.irradiance.abs().max(r.floor);
      per_probe.push_back({{"samples", e.samples},
                           {"converged", e.converged},
                           {"relative_se", rel.maxCoeff()},
                           {"truncated_paths", e.truncated}});
    }
    const nlohmann::json j = {
        {"hrad", {{"version", kVersion}, {"git_revision", git_revision()}}},
        {"command_line", ctx.argv},
        {"scene",
         {{"name", scene.name},
          {"source", scene.source},
          {"sides", a.scene_keys.sides},
          {"emitter_sides", a.scene_keys.emitter_sides},
          {"segments", a.scene_keys.segments},
          {"polygons", scene.polygon_count()},
          {"back_faces", scene.back_faces}}},
        {"options",
         {{"rel_error", a.options.rel_error},
          {"abs_floor", a.options.abs_floor},
          {"max_samples", a.options.max_samples},
          {"seed", a.options.seed},
          {"threads", a.options.threads},
          {"batch_size", a.options.batch_size},
          {"min_batches", a.options.min_batches},
          {"rr_depth", a.options.rr_depth}}},
        {"floor", {r.floor[0], r.floor[1], r.floor[2]}},
        {"probes", probes.size()},
        {"probes_file", a.random_probes > 0 ? "probes.txt (random surface probes)" : a.probes},
        {"samples_total", total},
        {"rounds", r.rounds},
        {"rays_cast", r.rays},
        {"wall_s", r.seconds},
        {"converged", unconverged.empty()},
        {"unconverged_probes", unconverged},
        {"per_probe", per_probe},
    };
    write_json_atomically(out / "reference.json", j);
    if (truncated > 0)
      fmt::print(stderr,
                 "hrad: warning: {} path(s) at {} probe(s) reached {} bounces and were cut: the "
                 "scene keeps (nearly) all the light it receives (reflectance 1 in a closed "
                 "scene has no finite solution); those probes' values are truncated sums, "
                 "marked unconverged\n",
                 truncated, truncated_probes, PathTracer::kMaxBounces);

    std::string list;  // unconverged for want of samples (not cut paths)
    std::size_t short_of_samples = 0;
    for (const auto& i : unconverged)
      if (r.probes[i.get<std::size_t>()].truncated == 0) {
        list += (list.empty() ? "" : ", ") + std::to_string(i.get<std::size_t>());
        ++short_of_samples;
      }
    if (short_of_samples > 0)
      fmt::print(stderr,
                 "hrad: warning: {} of {} probes did not reach {} relative error within {} "
                 "samples (0-based): {}\n",
                 short_of_samples, probes.size(), percent_text(a.options.rel_error),
                 a.options.max_samples, list);
    if (!a.quiet)
      fmt::print(
          "Reference for {}: {} probes, {} paths, {} rays in {:.3g} s ({} round{}), {} "
          "converged to {} relative error. Results in {}: probes.csv, reference.json.\n",
          a.scene, probes.size(), total, r.rays, r.seconds, r.rounds, r.rounds == 1 ? "" : "s",
          probes.size() - unconverged.size(), percent_text(a.options.rel_error), out.string());
  } catch (const std::exception& e) {
    std::error_code ec;
    const bool remove = created && fs::is_empty(out, ec);
    if (remove) fs::remove(out, ec);
    if (const auto* stop = dynamic_cast<const Interrupted*>(&e)) {
      print_error(fmt::format("{}: the reference stopped before writing any result{}", e.what(),
                              remove ? fmt::format(" (removed {})", out.string()) : ""));
      return stop->exit_status();
    }
    print_error(e.what());
    return 1;
  }
  return 0;
}

}  // namespace

void register_reference(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<ReferenceArgs>();
  CLI::App* sub = app.add_subcommand(
      "reference",
      "Path-traced reference irradiance at probe points (writes probes.csv, reference.json).");
  sub->add_option("SCENE", args->scene,
                  "Scene: FILE.obj (with its .mtl), FILE.mgf, or builtin:NAME[,k=v,...]")
      ->required();
  CLI::Option* probes =
      sub->add_option("--probes", args->probes,
                      "Irradiance probes: one 'x y z nx ny nz' per line (scene units)")
          ->type_name("FILE");
  CLI::Option* random =
      sub->add_option("--random-probes", args->random_probes,
                      "Instead of --probes: N points drawn uniformly by area over the scene's "
                      "faces (from --seed), on their front sides; written to DIR/probes.txt for "
                      "'hrad solve --probes'")
          ->type_name("N")
          ->transform(integer_in(1, std::uint64_t{1} << 20));
  probes->excludes(random);
  sub->add_option("-o,--out", args->out, "Output folder, created if missing, files in it replaced")
      ->type_name("DIR")
      ->required();
  sub->add_option("--rel-error", args->options.rel_error,
                  "Stop a probe when its standard error is below this fraction of its "
                  "irradiance (per channel, with the floor; 0.01 is 1 %) [default: 0.01]")
      ->type_name("X")
      ->check(number_in(1e-6, 1));
  sub->add_option("--floor", args->options.abs_floor,
                  "Absolute irradiance floor of the relative-error test [default: 1e-3 x the "
                  "mean probe irradiance]")
      ->type_name("X")
      ->check(number_in(0, 1e30));
  sub->add_option("--max-samples", args->options.max_samples,
                  fmt::format("Paths per probe at most [default: {}]", args->options.max_samples))
      ->type_name("N")
      ->transform(integer_in(1, 1'000'000'000'000'000));
  sub->add_option("--batch-size", args->options.batch_size,
                  "Paths per batch (the standard error comes from batch means) [default: 64]")
      ->type_name("N")
      ->transform(integer_in(1, std::uint64_t{1} << 20));
  sub->add_option("--seed", args->options.seed, "Mixed into every random number [default: 1]")
      ->type_name("N")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()));
  sub->add_option("-t,--threads", args->options.threads,
                  "OpenMP threads; results do not depend on it [default: 1]")
      ->type_name("N")
      ->transform(integer_in(1, kMaxThreads));
  // The scene's own keys, with the help text of `hrad solve`'s flags.
  const SolverOptions defaults;
  auto scene_key_help = [&](const char* key) {
    const std::string& h = find_option(key)->help;
    return fmt::format("{}{}, as for 'hrad solve' [config key {}; default {}]",
                       static_cast<char>(std::toupper(static_cast<unsigned char>(h[0]))),
                       h.substr(1), key, option_value_string(defaults, key));
  };
  sub->add_option("--sides", args->sides, scene_key_help("sides"))->type_name("MODE");
  sub->add_option("--emitter-sides", args->emitter_sides, scene_key_help("emitter_sides"))
      ->type_name("MODE");
  sub->add_option("--segments", args->scene_keys.segments, scene_key_help("segments"))
      ->type_name("N")
      ->transform(integer_in(0, 4096));
  sub->add_flag("--quiet", args->quiet, "No progress line and no summary");
  sub->callback([args, &ctx] {
    install_interrupt_handlers();  // stops at a safe point (core/base/interrupt.h)
    ctx.status = run_reference(*args, ctx);
  });
}

}  // namespace hrad::cli

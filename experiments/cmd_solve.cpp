// `hrad solve SCENE [options]`: load a scene, resolve the options, run the Solver and
// write the result files.
//
// Order of events, chosen so that bad input never leaves an output folder behind:
//   1. options: defaults < --config FILE < explicit flags < --set key=value; validate;
//   2. the scene (and the --probes file, the camera's view file): InputError ->
//      "hrad: <file:line: what>"; the camera (choose_camera);
//   3. the Solver is constructed (an unknown scheduler or oracle is reported here);
//   every failure so far exits with status 1 and creates nothing. Then
//   4. the output folder is created (--out DIR, default results/<scene>-<time>/);
//   5. the Solver runs with a progress line on terminals;
//   6. solution.ply, render.png (or --image FILE), probes.csv, and last stats.json,
//      each written atomically. stats.json lists the files actually written and, if
//      one failed, the error. A run that fails before writing anything removes the
//      folder if it created it.
#include "core/base/clock.h"
#include "core/base/input_error.h"
#include "core/base/input_file.h"
#include "core/base/interrupt.h"
#include "core/base/json_input.h"
#include "core/base/progress.h"
#include "core/base/provenance.h"
#include "core/config/options_io.h"
#include "core/output/auto_camera.h"
#include "core/output/pfm.h"
#include "core/output/ply_writer.h"
#include "core/output/render.h"
#include "core/output/stats_json.h"
#include "core/parallel/topology.h"
#include "core/scene/camera_spec.h"
#include "core/scene/probes.h"
#include "core/scene/scene_builder.h"
#include "core/scene/scene_loader.h"
#include "core/solver/solver.h"
#include "experiments/commands.h"
#include "experiments/harness/manifest.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

namespace hrad::cli {
namespace {

namespace fs = std::filesystem;

// The flags that set one SolverOptions key each. Their help text comes from the key
// table (core/config/options_io.cpp) plus the default, so the two cannot drift apart.
struct OptionFlag {
  const char* flag;
  const char* key;
  const char* value_name;
  const char* short_flag = nullptr;  ///< e.g. "-t", or none
};
constexpr OptionFlag kOptionFlags[] = {
    {"--scheduler", "scheduler", "NAME"},
    {"--block-size", "block_size", "N"},
    {"--threads", "threads", "N", "-t"},
    {"--oracle", "oracle", "NAME"},
    {"--eps", "eps", "X"},
    {"--min-area", "min_area", "X"},
    {"--iterations", "iterations", "N"},
    {"--pin", "pin", "POLICY"},
    {"--placement", "placement", "POLICY"},
    {"--seed", "seed", "N"},
    {"--sides", "sides", "MODE"},
    {"--emitter-sides", "emitter_sides", "MODE"},
    {"--segments", "segments", "N"},
    {"--shading", "shading", "MODE"},
    {"--exposure", "exposure", "STOPS"},
};

struct SolveArgs {
  std::string scene;
  std::string config, probes, image, hdr, out;
  std::string camera, view;  ///< --camera SPEC, --view FILE
  CLI::Option* camera_option = nullptr;
  std::vector<std::string> sets;
  std::vector<long long> explain;  ///< --explain-probe N (repeatable)
  bool quiet = false;
  std::map<std::string, std::string> flag_values;  ///< key -> text, for flags given
  std::map<std::string, CLI::Option*> flag_options;
};

// Leaves, and links per element, that --explain-probe lists.
constexpr int kExplainTop = 12;

struct Failure {
  std::string message;
};

/// The --config file as JSON (comments allowed). Throws, naming the file, when it is not
/// a regular file, cannot be opened or is not valid JSON.
nlohmann::json read_config_document(const std::string& config) {
  check_input_file(config, "the config file");
  std::ifstream in(config);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot open the config file", config));
  std::stringstream text;
  text << in.rdbuf();
  return parse_json_document<nlohmann::json>(text.str(), config, /*comments=*/true);
}

/// With no SCENE: the scene of an earlier run whose stats.json is the --config, by its
/// absolute path (stats.json "scene.path") while that file exists, else as the run named
/// it ("scene.source", a built-in scene or a path from the run's folder); "" when the
/// config is none or not a stats.json (then SCENE is missing). Throws for a config that
/// cannot be read, with what is wrong with it.
std::string scene_of_stats_config(const std::string& config) {
  if (config.empty()) return "";
  const nlohmann::json doc = read_config_document(config);
  if (!doc.is_object() || !doc.contains("totals") || !doc.contains("scene") ||
      !doc["scene"].is_object())
    return "";
  const nlohmann::json& sc = doc["scene"];
  if (sc.contains("path") && sc["path"].is_string()) {
    const auto path = sc["path"].get<std::string>();
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return path;
  }
  if (sc.contains("source") && sc["source"].is_string()) return sc["source"].get<std::string>();
  return "";
}

/// Resolves the options; `camera_from` says who set the camera key last: "config",
/// "option" (--camera or --set camera=...) or "" (nobody).
SolverOptions resolve_options(const SolveArgs& a, std::string& camera_from) {
  SolverOptions o;
  if (!a.config.empty()) {
    const nlohmann::json doc = read_config_document(a.config);
    // A solve's stats.json holds its complete configuration under "config": the run
    // again, with these flags on top.
    const bool stats = doc.is_object() && doc.contains("totals") && doc.contains("config") &&
                       doc["config"].is_object();
    const nlohmann::json& j = stats ? doc["config"] : doc;
    apply_options_json(o, j, a.config);
    if (j.contains("camera")) camera_from = "config";
  }
  for (const OptionFlag& f : kOptionFlags)
    if (a.flag_options.at(f.key)->count() > 0)
      apply_option_value(o, f.key, a.flag_values.at(f.key), f.flag);
  if (a.camera_option->count() > 0) {
    apply_option_value(o, "camera", a.camera, "--camera");
    camera_from = "option";
  }
  for (const std::string& s : a.sets) {
    apply_option_assignment(o, s);
    const OptionInfo* info = find_option(s.substr(0, s.find('=')));
    if (info && info->name == "camera") camera_from = "option";
  }
  validate_options(o);
  return o;
}

/// The camera of render.png and how it was chosen (stats.json "camera").
struct ChosenCamera {
  Camera camera;
  std::string source;     ///< "option", "view file", "config", "scene", "automatic"
  std::string view_file;  ///< for "view file"
  AutoCamera automatic;   ///< for "automatic"
  int up_axis = -1;       ///< "automatic" with --camera up=...: its axis
};

/// First of: the camera key set on the command line (--camera, --set camera=...),
/// --view FILE, the camera key of --config, SCENE.view beside a scene file, the
/// scene's own camera (built-in scenes), the automatic camera. "auto" as the key's
/// value skips to the last. The automatic camera itself is left to the caller.
ChosenCamera choose_camera(const SolveArgs& a, const SolverOptions& o,
                           const std::string& camera_from, const Scene& scene) {
  if (!a.view.empty() && camera_from == "option")
    throw std::invalid_argument(
        "--view and --camera (or --set camera=...) both give the camera: use one of them");
  const Vec3 up = Vec3::Unit(scene.up_axis());
  ChosenCamera c;
  auto automatic = [&] {
    c.source = "automatic";  // chosen once the solver's ray scene exists
    return c;
  };
  auto from_view_file = [&](const fs::path& file) {
    c.view_file = file.string();
    try {
      c.camera = resolve_camera(read_view_file(file), up);
    } catch (const std::invalid_argument& e) {
      throw InputError(c.view_file, 0, e.what());
    }
    c.source = "view file";
    return c;
  };
  auto from_key = [&](const char* source) {
    if (is_auto_camera(o.camera)) return automatic();
    try {
      if (const std::optional<int> axis = automatic_camera_up(o.camera)) {
        c.up_axis = *axis;  // the automatic camera, with this up axis
        return automatic();
      }
      c.camera = resolve_camera(parse_camera_spec(o.camera), up);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("option camera = '{}': {}", o.camera, e.what()));
    }
    c.source = source;
    return c;
  };
  if (camera_from == "option" && !o.camera.empty()) return from_key("option");
  if (!a.view.empty()) return from_view_file(a.view);
  if (camera_from == "config" && !o.camera.empty()) return from_key("config");
  if (a.scene.rfind("builtin:", 0) != 0) {
    const fs::path sibling = fs::path(a.scene).replace_extension(".view");
    std::error_code ec;
    if (fs::is_regular_file(sibling, ec)) return from_view_file(sibling);
  }
  if (scene.camera) {
    c.camera = *scene.camera;
    c.source = "scene";
    return c;
  }
  return automatic();
}

// results/<scene>-<YYYYmmdd-HHMMSS>/, made unique with -2, -3 ... when taken.
fs::path default_out_dir(const Scene& scene) {
  std::string name = scene.name.empty() ? "scene" : scene.name;
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  const fs::path base = fs::path("results") / (name + "-" + experiment::now_stamp());
  fs::path dir = base;
  for (int i = 2; fs::exists(dir); ++i) dir = base.string() + "-" + std::to_string(i);
  return dir;
}

bool is_empty_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir, ec) && fs::is_empty(dir, ec);
}

nlohmann::json topology_json() {
  try {
    const TopologyInfo t = discover_topology();
    return {{"packages", t.packages}, {"numa_nodes", t.numa_nodes},   {"cores", t.cores},
            {"pus", t.pus},           {"description", t.description}, {"synthetic", t.synthetic}};
  } catch (const std::exception& e) {
    return {{"error", e.what()}};
  }
}

void print_summary(const SolveArgs& a, const Scene& scene, const SolverOptions& o,
                   const RunStats& st, const fs::path& out, const std::vector<std::string>& files) {
  const RunTotals& t = st.totals;
  std::string listed;
  for (const std::string& f : files)
    if (f != a.image && f != a.hdr) listed += (listed.empty() ? "" : ", ") + f;
  // --image FILE and --hdr FILE are relative to where hrad runs, not to the output folder.
  if (!a.image.empty()) listed += "; image " + a.image;
  if (!a.hdr.empty()) listed += "; HDR image " + a.hdr;
  fmt::print(
      "Solved {} ({} polygons, {} emitting) with {} iteration{} of scheduler '{}', oracle '{}' "
      "on {} thread{}: {} links, {} elements, {} rays cast ({} visibility queries answered "
      "without rays); {:.3g} s wall: refinement {:.3g} s wall / {:.3g} s CPU, propagation "
      "{:.3g} s. Results in {}: {}.\n",
      a.scene, scene.polygon_count(), scene.emitter_count(), st.iterations.size(),
      st.iterations.size() == 1 ? "" : "s", o.scheduler, o.oracle, o.threads,
      o.threads == 1 ? "" : "s", t.links, t.elements, t.rays_cast, t.rays_skipped, t.wall_s,
      t.refine_wall_s, t.refine_cpu_s, t.propagate_wall_s, out.string(), listed);
}

// The configuration as stats.json records it: the options, with the trace as given (a
// relative one is inside the output folder), so that --config stats.json repeats it.
nlohmann::json config_json(const SolverOptions& o, const std::string& trace_given) {
  nlohmann::json j = options_to_json(o);
  j["trace"] = trace_given;
  return j;
}

// Refuses, before anything is loaded, an image that would not fit under max_memory_gb.
void check_image_memory(const SolverOptions& o) {
  const int height = std::max(1, o.image_width * 3 / 4);
  const double need = kRenderBytesPerPixel * o.image_width * height;
  const std::uint64_t limit = memory_limit_bytes(o.max_memory_gb);
  if (limit > 0 && need > static_cast<double>(limit))
    throw std::invalid_argument(fmt::format(
        "image_width {}: rendering {} x {} pixels needs about {:.3g} GB, above {}: lower "
        "image_width or raise max_memory_gb",
        o.image_width, o.image_width, height, need / 1e9, memory_limit_text(limit)));
}

int run_solve(const SolveArgs& a, const CommandContext& ctx) {
  // 1-3: everything that can be wrong with the input, before anything is created.
  SolverOptions options;
  Scene scene;
  double scene_load_s = 0;
  std::vector<Probe> probes;
  std::unique_ptr<ProgressReporter> progress;
  std::unique_ptr<Solver> solver;
  ChosenCamera camera;
  fs::path out;             // the output folder, created in step 4
  std::string trace_given;  // --set trace=FILE as given
  try {
    std::string camera_from;
    options = resolve_options(a, camera_from);
    check_image_memory(options);
    if (!a.image.empty()) {
      std::string ext = fs::path(a.image).extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".png")
        throw std::invalid_argument(fmt::format(
            "--image {}: the image is written as PNG, so its name must end in .png", a.image));
    }
    if (!a.hdr.empty()) {
      std::string ext = fs::path(a.hdr).extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".pfm")
        throw std::invalid_argument(fmt::format(
            "--hdr {}: the HDR image is written as a Portable Float Map, so its name must end "
            "in .pfm",
            a.hdr));
    }
    // Loading and preparing can take seconds on large scenes: the line says so.
    progress = std::make_unique<ProgressReporter>(a.quiet);
    progress->update("loading " + fs::path(a.scene).filename().string(), 0);
    const auto load_start = Clock::now();
    const MemoryGrowth load_memory;
    // max_memory_gb covers the load too, while it runs and at its end (the Solver checks
    // its preparation, the refinement its elements and links, the render its image).
    const std::uint64_t limit = memory_limit_bytes(options.max_memory_gb);
    {
      const MemoryBudget budget(limit, fmt::format("{}: loading the scene", a.scene));
      scene = load_scene(a.scene, scene_load_options(options));
    }
    scene_load_s = seconds_since(load_start);
    if (const std::uint64_t took = load_memory.grown(); limit > 0 && took > limit)
      throw std::invalid_argument(fmt::format(
          "{}: loading the scene ({} polygons) took {:.3g} GB of memory, above {}", a.scene,
          scene.polygon_count(), static_cast<double>(took) / 1e9, memory_limit_text(limit)));
    if (!a.probes.empty()) {
      probes = read_probes(a.probes);
      if (probes.empty())
        throw std::invalid_argument(
            fmt::format("{}: holds no probe (only comments or blank lines)", a.probes));
    }
    for (const long long n : a.explain) {
      if (a.probes.empty())
        throw std::invalid_argument(
            fmt::format("--explain-probe {}: needs --probes FILE (it explains one of them)", n));
      if (n < 0 || static_cast<std::size_t>(n) >= probes.size())
        throw std::invalid_argument(
            fmt::format("--explain-probe {}: {} holds probes 0..{} (counted from 0)", n, a.probes,
                        probes.size() - 1));
    }
    camera = choose_camera(a, options, camera_from, scene);
    if (camera.up_axis >= 0) scene.declared_up = camera.up_axis;
    if (!scene.warnings.empty()) progress->finish();  // warnings start on a clean line
    for (const std::string& w : scene.warnings)
      if (w != kNoEmitterWarning)  // the solver says it, with what it skipped
        fmt::print(stderr, "hrad: warning: {}\n", w);
    progress->update("preparing (hierarchy, rays, effects)", 0);
    out = a.out.empty() ? default_out_dir(scene) : fs::path(a.out);
    // A task trace goes with the run's other results: a relative path is inside the
    // output folder (the Solver refuses a target that is not a trace before it starts;
    // normal form, so that it checks run/../scene.obj as scene.obj, not through a
    // folder that does not exist yet).
    trace_given = options.trace;
    if (!options.trace.empty() && fs::path(options.trace).is_relative())
      options.trace = (out / options.trace).lexically_normal().string();
    solver = std::make_unique<Solver>(scene, options, progress->callback());
    if (camera.source == "automatic") {
      camera.automatic = automatic_camera(scene, solver->ray_scene());
      camera.camera = camera.automatic.camera;
    }
  } catch (const Interrupted& e) {
    if (progress) progress->finish();
    print_error(fmt::format("{}: the solve stopped before writing any result", e.what()));
    return e.exit_status();
  } catch (const std::exception& e) {
    if (progress) progress->finish();
    print_error(e.what());
    return 1;
  }

  // 4: the output folder.
  bool created = false;
  if (!make_output_folder(out, created)) return 1;
  // Results of an earlier run into the same folder go first: a file this run does not
  // write (probes.csv of a run with probes, followed by one without) must not pass for
  // its result. Other files in the folder are left alone.
  for (const char* name : {"stats.json", "solution.ply", "render.png", "probes.csv"}) {
    std::error_code ec;
    fs::remove(out / name, ec);
  }
  {
    std::error_code ec;
    std::vector<fs::path> explained;
    for (const auto& f : fs::directory_iterator(out, ec)) {
      const std::string name = f.path().filename().string();
      if (name.starts_with("explain-probe-") && name.ends_with(".json"))
        explained.push_back(f.path());
    }
    for (const fs::path& f : explained) fs::remove(f, ec);
  }

  // 5-6: run and write. stats.json comes last so that it lists what was written.
  std::vector<std::string> written;  // paths as given to the user
  nlohmann::json outputs = nlohmann::json::object();
  std::optional<Failure> failure;
  RunStats stats;
  nlohmann::json image_info = nlohmann::json::object();
  try {
    const std::string started = experiment::now_iso8601();
    stats = solver->run();
    stats.totals.scene_load_s = scene_load_s;
    if (!trace_given.empty()) {
      outputs["trace"] = trace_given;  // inside the folder when relative
      if (fs::path(trace_given).is_relative()) written.push_back(trace_given);
    }
    progress->finish();
    const auto mesh_start = Clock::now();
    const RenderMesh mesh = solver->render_mesh(options.shading);
    image_info["shading"] = enum_name(options.shading);
    image_info["mesh_s"] = seconds_since(mesh_start);
    image_info["mesh_vertices"] = mesh.positions.size();
    image_info["mesh_polygons"] = mesh.polys.size();

    ToneMap tone;
    tone.stops = options.exposure;
    try {
      write_ply(mesh, out / "solution.ply", tone);
      outputs["mesh"] = "solution.ply";
      written.push_back("solution.ply");

      const fs::path image = a.image.empty() ? out / "render.png" : fs::path(a.image);
      if (!a.image.empty() && image.has_parent_path()) fs::create_directories(image.parent_path());
      const int width = options.image_width;
      const int height = std::max(1, width * 3 / 4);
      const auto render_start = Clock::now();
      const Image img = render_radiance(mesh, camera.camera, width, height, options.image_samples);
      image_info["width"] = width;
      image_info["height"] = height;
      image_info["samples_per_pixel"] = options.image_samples * options.image_samples;
      image_info["render_s"] = seconds_since(render_start);
      const double k = write_png(img, image, tone);
      image_info["exposure"] = {{"stops", options.exposure},
                                {"automatic", k / std::exp2(options.exposure)},
                                {"applied", k}};
      outputs["image"] = a.image.empty() ? "render.png" : a.image;
      written.push_back(a.image.empty() ? "render.png" : a.image);

      if (!a.hdr.empty()) {
        const fs::path hdr(a.hdr);
        if (hdr.has_parent_path()) fs::create_directories(hdr.parent_path());
        write_pfm(img, hdr);
        outputs["hdr"] = a.hdr;
        written.push_back(a.hdr);
      }

      if (!a.probes.empty()) {
        const std::vector<Rgb> e = solver->probe_irradiance(probes, progress->callback());
        progress->finish();
        write_probes_csv(out / "probes.csv", probes, e);
        outputs["probes"] = "probes.csv";
        written.push_back("probes.csv");
        for (const long long n : a.explain) {
          const auto i = static_cast<std::size_t>(n);
          const std::string name = fmt::format("explain-probe-{}.json", i);
          write_json_atomically(out / name, solver->explain_probe(i, probes[i], kExplainTop));
          outputs["explain"].push_back(name);
          written.push_back(name);
        }
      }
    } catch (const Interrupted&) {
      throw;
    } catch (const std::exception& e) {
      failure = Failure{e.what()};
    }

    nlohmann::json j = {
        {"hrad",
         {{"version", kVersion},
          {"git_revision", git_revision()},
          {"compiler", build_info().compiler}}},
        {"command_line", ctx.argv},
        {"started_at", started},
        {"config", config_json(options, trace_given)},
        {"config_file", a.config.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.config)},
        {"scene", scene_summary_json(scene)},
        {"camera", camera_json(camera.camera, camera.source, camera.view_file)},
        {"image", image_info},
        {"topology", topology_json()},
    };
    if (camera.source == "automatic")
      j["camera"]["automatic"] = {{"view", camera.automatic.view},
                                  {"rays", camera.automatic.rays},
                                  {"seconds", camera.automatic.seconds}};
    j.update(stats_to_json(stats));
    // Top-level warnings: the scene's first, then the solver's.
    nlohmann::json warnings = scene.warnings;
    for (const std::string& w : stats.warnings) warnings.push_back(w);
    j["warnings"] = std::move(warnings);
    j["outputs"] = outputs;
    if (failure) j["error"] = failure->message;
    write_json_atomically(out / "stats.json", j);
    written.insert(written.begin(), "stats.json");
  } catch (const Interrupted& e) {
    // Stopped at a safe point. What this run had written goes (the results of an
    // earlier run into the folder were removed at the start): a mesh and an image
    // without stats.json would pass for a result.
    progress->finish();
    for (const std::string& f : written) {
      std::error_code ec;
      fs::remove(f == a.image || f == a.hdr ? fs::path(f) : out / f, ec);
    }
    const bool remove = created && is_empty_dir(out);
    if (remove) fs::remove(out);
    print_error(fmt::format("{}: the solve stopped before writing any result{}", e.what(),
                            remove ? fmt::format(" (removed {})", out.string()) : ""));
    return e.exit_status();
  } catch (const std::exception& e) {
    if (!failure) failure = Failure{e.what()};
  }
  progress->finish();

  if (failure) {
    print_error(failure->message);
    if (created && is_empty_dir(out)) fs::remove(out);
    return 1;
  }
  for (const std::string& w : stats.warnings) fmt::print(stderr, "hrad: warning: {}\n", w);
  if (!a.quiet) print_summary(a, scene, options, stats, out, written);
  return 0;
}

}  // namespace

void register_solve(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<SolveArgs>();
  CLI::App* sub = app.add_subcommand(
      "solve", "Solve one scene and write stats.json, solution.ply and render.png.");
  sub->add_option("SCENE", args->scene,
                  "Scene to solve: FILE.obj (with its .mtl), FILE.mgf, or builtin:NAME[,k=v,...] "
                  "(see 'hrad scenes'); may be left out when --config is an earlier run's "
                  "stats.json, whose scene is then solved again");

  const SolverOptions defaults;
  for (const OptionFlag& f : kOptionFlags) {
    const OptionInfo* info = find_option(f.key);
    const std::string help =
        fmt::format("{}{} [config key {}; default {}]",
                    static_cast<char>(std::toupper(static_cast<unsigned char>(info->help[0]))),
                    info->help.substr(1), f.key, option_value_string(defaults, f.key));
    args->flag_options[f.key] =
        sub->add_option(f.short_flag ? fmt::format("{},{}", f.short_flag, f.flag) : f.flag,
                        args->flag_values[f.key], help)
            ->type_name(f.value_name);
  }
  sub->add_option("--probes", args->probes,
                  "Irradiance probes: a text file with one 'x y z nx ny nz' per line (scene "
                  "units); writes probes.csv [default: none]")
      ->type_name("FILE");
  sub->add_option("--explain-probe", args->explain,
                  fmt::format("Write explain-probe-N.json: where probe N (of --probes, counted "
                              "from 0) gets its irradiance, its {} strongest leaves and the "
                              "links of every element above the strongest; repeatable",
                              kExplainTop))
      ->type_name("N")
      ->transform(integer_in(0, std::uint64_t{1} << 32));
  sub->add_option("--image", args->image,
                  "Write the rendered image to FILE instead of DIR/render.png (PNG; missing "
                  "folders are created)")
      ->type_name("FILE");
  sub->add_option("--hdr", args->hdr,
                  "Also write the image's linear radiance (B/pi per pixel) to FILE, a "
                  "little-endian Portable Float Map (.pfm; missing folders are created) "
                  "[default: none]")
      ->type_name("FILE");
  sub->add_option("-o,--out", args->out,
                  "Output folder, created if missing, files in it replaced [default: "
                  "results/<scene>-<YYYYmmdd-HHMMSS>/ in the current directory]")
      ->type_name("DIR");
  args->camera_option =
      sub->add_option("--camera", args->camera,
                      "Camera of the image: eye=X,Y,Z:look=X,Y,Z[:up=X,Y,Z][:fov=DEG] (up: the "
                      "scene's up axis, fov: 60 degrees, by default), or auto, or up=X,Y,Z "
                      "alone (the automatic camera with up along +x, +y or +z); sets config "
                      "key camera [default: --view, the config's camera, SCENE.view, the "
                      "scene's own, else automatic]")
          ->type_name("SPEC");
  sub->add_option("--view", args->view,
                  "Camera of the image from a view file: lines 'eye X Y Z', 'look X Y Z', "
                  "optional 'up X Y Z' and 'fov DEG', # comments (see docs/cli.md)")
      ->type_name("FILE");
  sub->add_option("--config", args->config,
                  "JSON file of option keys (see docs/configuration.md), or an earlier run's "
                  "stats.json (its \"config\"); explicit flags and --set override it "
                  "[default: none]")
      ->type_name("FILE");
  sub->add_option("--set", args->sets,
                  fmt::format("Set any option key, after --config and the flags; repeatable; "
                              "'.' or '-' may replace '_' in KEY. Keys: {}",
                              option_key_list()))
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_flag("--quiet", args->quiet,
                "No progress line and no summary (warnings and errors are still printed)");

  sub->callback([args, &ctx] {
    if (args->scene.empty()) {
      try {
        args->scene = scene_of_stats_config(args->config);
      } catch (const std::exception& e) {  // the config cannot be read: say why
        print_error(e.what());
        ctx.status = 1;
        return;
      }
    }
    if (args->scene.empty()) throw CLI::RequiredError("SCENE");
    install_interrupt_handlers();  // stops at a safe point (core/base/interrupt.h)
    ctx.status = run_solve(*args, ctx);
  });
}

}  // namespace hrad::cli

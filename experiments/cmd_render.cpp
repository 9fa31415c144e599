// `hrad render RESULT`: a new picture of a solved scene without solving it again, from
// the solution.ply a solve wrote (core/scene/ply_reader.h), with another camera, size,
// antialiasing or exposure. RESULT is a solve's output folder or a solution.ply; the
// folder's stats.json gives the defaults (the solve's camera, image size, samples and
// exposure). The picture is the solve's: the same mesh, camera model and tone mapping
// (core/output/render.h), from the mesh's 32-bit floats. Nothing in RESULT but the
// new image is written.
#include "core/base/json_input.h"
#include "core/output/pfm.h"
#include "core/output/render.h"
#include "core/scene/camera_spec.h"
#include "core/scene/ply_reader.h"
#include "core/solver/solver.h"
#include "experiments/commands.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

namespace hrad::cli {
namespace {

namespace fs = std::filesystem;

struct RenderArgs {
  std::string result, camera, view, image, hdr;
  int width = 0, samples = 0;
  std::optional<double> exposure;
  std::optional<double> max_memory_gb;  ///< none: the solve's (config.max_memory_gb)
};

// What a solve's stats.json says about its picture; empty when RESULT has none.
struct SolvedPicture {
  fs::path dir;                  // RESULT, or the folder of the solution.ply given
  fs::path mesh;                 // the solution.ply
  std::string camera_spec;       // camera.spec
  Vec3 up = Vec3(0, 1, 0);       // camera.up: the default up of a new camera
  int width = 640, samples = 2;  // image.width, sqrt of image.samples_per_pixel
  double stops = 0;              // image.exposure.stops
  double max_memory_gb = 0;      // config.max_memory_gb
};

SolvedPicture read_result(const fs::path& result) {
  SolvedPicture p;
  p.dir = result;
  if (fs::is_regular_file(result)) {
    p.mesh = result;
    p.dir = result.parent_path().empty() ? fs::path(".") : result.parent_path();
  } else if (!fs::is_directory(result)) {
    throw std::invalid_argument(
        fmt::format("{}: neither a solve's output folder nor a solution.ply", result.string()));
  }
  const fs::path stats = p.dir / "stats.json";
  std::ifstream in(stats);
  if (!in) {
    if (p.mesh.empty())
      throw std::invalid_argument(fmt::format(
          "{}: no stats.json, so not a solve's output folder (give its solution.ply and "
          "--camera)",
          result.string()));
    return p;  // a bare solution.ply: nothing known but the mesh
  }
  std::stringstream text;
  text << in.rdbuf();
  const auto j = parse_json_document<nlohmann::json>(text.str(), stats.string(), false);
  const auto str = [&](const nlohmann::json& at, const char* key) -> const nlohmann::json* {
    const auto it = at.find(key);
    return it != at.end() ? &*it : nullptr;
  };
  if (p.mesh.empty()) {
    const nlohmann::json* outputs = str(j, "outputs");
    const nlohmann::json* mesh = outputs && outputs->is_object() ? str(*outputs, "mesh") : nullptr;
    if (!mesh || !mesh->is_string())
      throw std::invalid_argument(fmt::format(
          "{}: lists no mesh under outputs (the solve wrote no solution.ply)", stats.string()));
    p.mesh = p.dir / mesh->get<std::string>();
  }
  if (const nlohmann::json* c = str(j, "camera"); c && c->is_object()) {
    if (const nlohmann::json* s = str(*c, "spec"); s && s->is_string())
      p.camera_spec = s->get<std::string>();
    if (const nlohmann::json* u = str(*c, "up"); u && u->is_array() && u->size() == 3)
      p.up = Vec3((*u)[0].get<double>(), (*u)[1].get<double>(), (*u)[2].get<double>());
  }
  if (const nlohmann::json* img = str(j, "image"); img && img->is_object()) {
    if (const nlohmann::json* w = str(*img, "width"); w && w->is_number_integer())
      p.width = w->get<int>();
    if (const nlohmann::json* s = str(*img, "samples_per_pixel"); s && s->is_number())
      p.samples = std::max(1, static_cast<int>(std::lround(std::sqrt(s->get<double>()))));
    if (const nlohmann::json* e = str(*img, "exposure"); e && e->is_object())
      if (const nlohmann::json* s = str(*e, "stops"); s && s->is_number())
        p.stops = s->get<double>();
  }
  if (const nlohmann::json* c = str(j, "config"); c && c->is_object())
    if (const nlohmann::json* m = str(*c, "max_memory_gb"); m && m->is_number())
      p.max_memory_gb = m->get<double>();
  return p;
}

Camera choose(const RenderArgs& a, const SolvedPicture& p) {
  if (!a.view.empty()) return resolve_camera(read_view_file(a.view), p.up);
  const std::string spec = a.camera.empty() ? p.camera_spec : a.camera;
  if (spec.empty())
    throw std::invalid_argument(
        "no camera: the result has no stats.json to take the solve's "
        "from; give --camera eye=X,Y,Z:look=X,Y,Z or --view FILE");
  if (is_auto_camera(spec) || automatic_camera_up(spec))
    throw std::invalid_argument(
        "--camera " + spec +
        ": the automatic camera is chosen with rays against the scene, which `hrad render` "
        "does not load; give eye=X,Y,Z:look=X,Y,Z (the solve's camera is the default)");
  try {
    return resolve_camera(parse_camera_spec(spec), p.up);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("--camera '{}': {}", spec, e.what()));
  }
}

int run_render(const RenderArgs& a) {
  try {
    const SolvedPicture p = read_result(a.result);
    const Camera camera = choose(a, p);
    const int width = a.width > 0 ? a.width : p.width;
    const int height = std::max(1, width * 3 / 4);
    const int samples = a.samples > 0 ? a.samples : p.samples;
    // Checked before the mesh is read, as `hrad solve` checks image_width.
    const std::uint64_t limit = memory_limit_bytes(a.max_memory_gb.value_or(p.max_memory_gb));
    const double need = kRenderBytesPerPixel * width * height;
    if (limit > 0 && need > static_cast<double>(limit))
      throw std::invalid_argument(
          fmt::format("--width {}: rendering {} x {} pixels needs about {:.3g} GB, above {}: "
                      "lower --width or raise --max-memory-gb",
                      width, width, height, need / 1e9, memory_limit_text(limit)));
    const fs::path image = a.image.empty() ? p.dir / "rerender.png" : fs::path(a.image);
    if (fs::exists(image) && fs::equivalent(image, p.mesh))
      throw std::invalid_argument(fmt::format("--image {} is the mesh itself", image.string()));

    const RenderMesh mesh = read_ply(p.mesh);
    const Image img = render_radiance(mesh, camera, width, height, samples);
    ToneMap tone;
    tone.stops = a.exposure.value_or(p.stops);
    if (image.has_parent_path()) fs::create_directories(image.parent_path());
    const double k = write_png(img, image, tone);
    if (!a.hdr.empty()) {
      const fs::path hdr(a.hdr);
      if (hdr.has_parent_path()) fs::create_directories(hdr.parent_path());
      write_pfm(img, hdr);
    }
    fmt::print(
        "Rendered {} ({} polygons) with camera {}: {} x {} pixels, {} samples per "
        "pixel, exposure {:.4g} ({:+g} stops over automatic). Written: {}{}.\n",
        p.mesh.string(), mesh.polys.size(), camera_spec_string(camera), width, height,
        samples * samples, k, tone.stops, image.string(), a.hdr.empty() ? "" : ", " + a.hdr);
    return 0;
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }
}

}  // namespace

void register_render(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub = app.add_subcommand(
      "render",
      "A new picture of a solved scene from its solution.ply, without solving again: "
      "another camera, size, antialiasing or exposure. Defaults: the solve's (its "
      "stats.json).");
  sub->add_option("RESULT", args->result, "A solve's output folder, or a solution.ply")->required();
  sub->add_option("--camera", args->camera,
                  "eye=X,Y,Z:look=X,Y,Z[:up=X,Y,Z][:fov=DEG] (default: the solve's camera; "
                  "up defaults to the solve's up)")
      ->type_name("SPEC");
  sub->add_option("--view", args->view, "the camera from a view file (as `hrad solve --view`)")
      ->type_name("FILE")
      ->excludes("--camera");
  sub->add_option("--width", args->width,
                  "image width in pixels, 8-16384; the height is 3/4 of it (default: the "
                  "solve's)")
      ->type_name("N")
      ->transform(integer_in(8, 16384));
  sub->add_option("--samples", args->samples,
                  "N x N stratified rays per pixel, 1-16 (default: the solve's)")
      ->type_name("N")
      ->transform(integer_in(1, 16));
  sub->add_option("--exposure", args->exposure,
                  "stops over the automatic exposure, +1 twice as bright (default: the solve's)")
      ->type_name("STOPS")
      ->check(number_in(-64, 64));
  sub->add_option("--max-memory-gb", args->max_memory_gb,
                  "refuse, before rendering, an image that needs more memory than this many GB "
                  "(about 60 bytes a pixel; 0: 3/4 of the machine's physical memory; default: "
                  "the solve's max_memory_gb)")
      ->type_name("GB")
      ->check(number_in(0, 1e9));
  sub->add_option("--image", args->image,
                  "where to write the PNG (default: RESULT/rerender.png; the solve's "
                  "render.png is left alone unless named here)")
      ->type_name("FILE");
  sub->add_option("--hdr", args->hdr, "also write the linear radiance as a PFM image")
      ->type_name("FILE");
  sub->callback([args, &ctx] { ctx.status = run_render(*args); });
}

}  // namespace hrad::cli

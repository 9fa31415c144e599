// `hrad scenes`: the built-in scenes with their parameters, and the scene file formats.
#include "core/scene/builtin_scenes.h"
#include "experiments/commands.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

namespace hrad::cli {
namespace {

std::string number(double v, bool integer) {
  return integer ? fmt::format("{}", static_cast<long long>(v)) : fmt::format("{:g}", v);
}

void print_scenes() {
  fmt::print(
      "Built-in scenes. Use them as the SCENE of 'hrad solve', with optional\n"
      "parameters: builtin:NAME or builtin:NAME,key=value,key=value\n"
      "(e.g. builtin:office,desks=40,lights=6). The form\n"
      "'builtin:NAME?key=value&key=value' works too, in quotes (unquoted, the shell\n"
      "would run the command in the background at '&'). Every scene is a pure function\n"
      "of its spec.\n");
  for (const BuiltinInfo& s : builtin_scenes()) {
    fmt::print("\nbuiltin:{}\n  {}\n", s.name, s.description);
    if (s.params.empty()) {
      fmt::print("  (no parameters)\n");
      continue;
    }
    std::size_t name_w = 9, def_w = 7, range_w = 5;
    for (const BuiltinParam& p : s.params) {
      name_w = std::max(name_w, p.name.size());
      def_w = std::max(def_w, number(p.default_value, p.integer).size());
      range_w = std::max(
          range_w,
          (number(p.min_value, p.integer) + " .. " + number(p.max_value, p.integer)).size());
    }
    fmt::print("  {:<{}}  {:>{}}  {:<{}}  {}\n", "parameter", name_w, "default", def_w, "range",
               range_w, "meaning");
    for (const BuiltinParam& p : s.params)
      fmt::print("  {:<{}}  {:>{}}  {:<{}}  {}{}\n", p.name, name_w,
                 number(p.default_value, p.integer), def_w,
                 number(p.min_value, p.integer) + " .. " + number(p.max_value, p.integer), range_w,
                 p.meaning, p.integer ? " (integer)" : "");
  }
  fmt::print(
      "\nScene files (chosen by extension, case-insensitive):\n"
      "  FILE.obj  Wavefront OBJ with its .mtl: Kd is the diffuse reflectance (each channel\n"
      "            in [0,1]; above 1 is an error), Ke is read as emitted radiance, so the\n"
      "            exitance is pi * Ke. Planar convex polygons are kept, others triangulated.\n"
      "  FILE.mgf  Materials and Geometry Format 1.1 (RenderPark, Radiance): CIE colours\n"
      "            and rd / ed converted to RGB as documented in core/scene/mgf/mgf_color.h.\n"
      "See docs/formats.md for the details.\n");
}

}  // namespace

void register_scenes(CLI::App& app, CommandContext& ctx) {
  CLI::App* sub = app.add_subcommand(
      "scenes", "List the built-in scenes with their parameters, and the scene file formats.");
  sub->callback([&ctx] {
    print_scenes();
    ctx.status = 0;
  });
}

}  // namespace hrad::cli

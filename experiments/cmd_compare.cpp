// `hrad compare A B [--floor F] [--json FILE]`: error metrics of a result A against a
// reference B (core/reference/error_metrics.h).
//
//   A, B probes.csv files           probe metric
//   A, B run folders                probe metric when both hold probes.csv, surface
//                                   metric when both hold solution.ply (both when both)
// When both folders name their scene (stats.json or reference.json), the scene sources
// must agree. Prints a
// table on stdout; --json FILE writes the same numbers (atomically). Exit 1 with a
// message naming the files for anything that cannot be compared.
#include "core/base/json_input.h"
#include "core/output/stats_json.h"
#include "core/reference/error_metrics.h"
#include "core/scene/ply_reader.h"
#include "experiments/commands.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <utility>

namespace hrad::cli {
namespace {

namespace fs = std::filesystem;

struct CompareArgs {
  std::string a, b, json;
  double floor = 0;
  std::size_t samples = 200000;
  std::uint64_t seed = 1;
  bool per_probe = false;
};

nlohmann::json rgb_json(const Rgb& c) { return {c[0], c[1], c[2]}; }

/// What compare needs of a run folder, each JSON file read once: the scene it solved
/// (scene.source of DIR/stats.json for `solve`, else of DIR/reference.json for
/// `reference`; "" when neither says) and, for a solve folder, the files its stats.json
/// lists under `outputs`.
struct RunFolder {
  fs::path dir;
  std::string source;
  bool solve = false;  ///< DIR/stats.json exists
  nlohmann::json outputs = nlohmann::json::object();

  /// Throws unless DIR holds stats.json (`hrad solve`) or reference.json (`hrad
  /// reference`): files in any other folder are nobody's result that compare can vouch
  /// for (copied by hand, or left by another program).
  explicit RunFolder(fs::path d) : dir(std::move(d)) {
    if (!fs::exists(dir / "stats.json") && !fs::exists(dir / "reference.json"))
      throw std::invalid_argument(fmt::format(
          "{}: not an hrad result folder (it holds neither stats.json from 'hrad solve' nor "
          "reference.json from 'hrad reference'); to compare a probe table on its own, give "
          "the file ({})",
          dir.string(), (dir / "probes.csv").string()));
    if (std::ifstream in(dir / "stats.json"); in) {
      solve = true;
      std::stringstream text;
      text << in.rdbuf();
      try {
        const auto j =
            parse_json_document<nlohmann::json>(text.str(), (dir / "stats.json").string(), false);
        if (const auto o = j.find("outputs"); o != j.end() && o->is_object()) outputs = *o;
        source = j.at("scene").at("source").get<std::string>();
      } catch (const std::exception&) {
        // Unreadable, or no scene: nothing listed, and the scene from reference.json.
      }
    }
    if (!source.empty()) return;
    if (std::ifstream in(dir / "reference.json"); in) {
      try {
        source = nlohmann::json::parse(in).at("scene").at("source").get<std::string>();
      } catch (const std::exception&) {
      }
    }
  }

  /// Whether DIR holds the result file NAME for this comparison: a solve folder's
  /// stats.json must list it under outputs.KEY (a file the run did not write, left
  /// from an earlier run into the same folder, is not its result); a reference folder
  /// (reference.json, no stats.json) holds what is there.
  [[nodiscard]] bool holds(const char* key, const char* name) const {
    if (!fs::exists(dir / name)) return false;
    return !solve || outputs.value(key, "") == name;
  }
};

nlohmann::json probe_report(const ProbeTable& a, const ProbeTable& b, double floor, bool rows) {
  const ProbeComparison c = compare_probes(a, b, floor);
  fmt::print("Probes: {} ({} against reference {})\n", c.probes.size(), a.file, b.file);
  // Printed in percent (the JSON keeps fractions).
  fmt::print("  relative error |a - r| / max(|r|, {:.4g}), largest channel, in %:\n", c.floor);
  fmt::print("    median {:.3g} %   mean {:.3g} %   rms {:.3g} %   max {:.3g} % (probe {})\n",
             100 * c.median, 100 * c.mean, 100 * c.rms, 100 * c.max, c.worst);
  fmt::print("  signed error of the channel mean: mean (bias) {:+.3g} %, {} of {} probes low\n",
             100 * c.bias, c.low, c.probes.size());
  if (c.has_se)
    fmt::print("  within 2 standard errors of the reference: {} of {}\n", c.within_2se,
               c.probes.size());
  if (rows) {
    // E is the mean of the three channels; rel.err is the largest channel's, as above.
    fmt::print("  {:>5} {:>13} {:>13} {:>11}{}\n", "probe", "E mean (res)", "E mean (ref)",
               "rel.err %", c.has_se ? "     |d|/SE" : "");
    for (std::size_t i = 0; i < c.probes.size(); ++i) {
      const ProbeError& e = c.probes[i];
      fmt::print("  {:>5} {:>13.5g} {:>13.5g} {:>11.3g}", i, e.result.mean(), e.reference.mean(),
                 100 * e.rel_error);
      if (c.has_se) fmt::print(" {:>10.3g}", e.z);
      fmt::print("\n");
    }
  }
  nlohmann::json per = nlohmann::json::array();
  for (const ProbeError& e : c.probes) {
    nlohmann::json p = {{"result", rgb_json(e.result)},
                        {"reference", rgb_json(e.reference)},
                        {"rel_error", e.rel_error},
                        {"signed_error", e.signed_error}};
    if (c.has_se) p["z"] = e.z;
    per.push_back(p);
  }
  nlohmann::json j = {
      {"result", a.file}, {"reference", b.file}, {"floor", c.floor},   {"count", c.probes.size()},
      {"mean", c.mean},   {"rms", c.rms},        {"median", c.median}, {"bias", c.bias},
      {"low", c.low},     {"max", c.max},        {"worst", c.worst},   {"per_probe", per}};
  if (c.has_se) j["within_2se"] = c.within_2se;
  return j;
}

nlohmann::json surface_report(const fs::path& a, const fs::path& b, std::size_t samples,
                              std::uint64_t seed) {
  const RenderMesh ma = read_ply(a), mb = read_ply(b);
  const SurfaceComparison s = compare_surfaces(ma, mb, samples, seed);
  fmt::print(
      "Surfaces: {} ({} polygons) against reference {} ({} polygons), {} points, {} "
      "unmatched\n",
      a.string(), ma.polys.size(), b.string(), mb.polys.size(), s.samples, s.unmatched);
  fmt::print("  radiosity error relative to the reference's area-weighted mean, in %:\n");
  fmt::print("  {:>8} {:>10} {:>10} {:>10} {:>10}\n", "", "r", "g", "b", "all");
  fmt::print("  {:>8} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g}\n", "L1", 100 * s.l1[0],
             100 * s.l1[1], 100 * s.l1[2], 100 * s.l1_all);
  fmt::print("  {:>8} {:>10.4g} {:>10.4g} {:>10.4g} {:>10.4g}\n", "L2", 100 * s.l2[0],
             100 * s.l2[1], 100 * s.l2[2], 100 * s.l2_all);
  fmt::print("  {:>8} {:>10.4g} {:>10.4g} {:>10.4g}\n", "mean ref", s.reference_mean[0],
             s.reference_mean[1], s.reference_mean[2]);
  return {{"result", a.string()},
          {"reference", b.string()},
          {"polygons_result", ma.polys.size()},
          {"polygons_reference", mb.polys.size()},
          {"samples", s.samples},
          {"unmatched", s.unmatched},
          {"l1", rgb_json(s.l1)},
          {"l2", rgb_json(s.l2)},
          {"l1_all", s.l1_all},
          {"l2_all", s.l2_all},
          {"reference_mean", rgb_json(s.reference_mean)},
          {"area_result", s.area_result},
          {"area_reference", s.area_reference}};
}

int run_compare(const CompareArgs& args) {
  try {
    const fs::path a(args.a), b(args.b);
    for (const fs::path& p : {a, b})
      if (!fs::exists(p))
        throw std::invalid_argument(fmt::format("{}: no such file or folder", p.string()));
    nlohmann::json j = nlohmann::json::object();
    if (!fs::is_directory(a) || !fs::is_directory(b)) {
      // A folder against a file: the folder's probes.csv, if it is its run's.
      const auto probe_file = [](const fs::path& p) {
        if (!fs::is_directory(p)) return p;
        if (!RunFolder(p).holds("probes", "probes.csv"))
          throw std::invalid_argument(fmt::format(
              "{}: holds no probes.csv (in a solve folder, only the files its stats.json lists "
              "under 'outputs' count)",
              p.string()));
        return p / "probes.csv";
      };
      j["probes"] = probe_report(read_probe_table(probe_file(a)), read_probe_table(probe_file(b)),
                                 args.floor, args.per_probe);
    } else {
      const RunFolder fa(a), fb(b);
      if (!fa.source.empty() && !fb.source.empty() && fa.source != fb.source)
        throw std::invalid_argument(
            fmt::format("{} solved '{}' but {} solved '{}': not the same scene", a.string(),
                        fa.source, b.string(), fb.source));
      const bool probes = fa.holds("probes", "probes.csv") && fb.holds("probes", "probes.csv");
      const bool surfaces = fa.holds("mesh", "solution.ply") && fb.holds("mesh", "solution.ply");
      if (!probes && !surfaces)
        throw std::invalid_argument(fmt::format(
            "nothing to compare: {} and {} do not both hold probes.csv or both solution.ply "
            "(in a solve folder, only the files its stats.json lists under 'outputs' count)",
            a.string(), b.string()));
      if (probes)
        j["probes"] = probe_report(read_probe_table(a / "probes.csv"),
                                   read_probe_table(b / "probes.csv"), args.floor, args.per_probe);
      if (surfaces)
        j["surfaces"] =
            surface_report(a / "solution.ply", b / "solution.ply", args.samples, args.seed);
    }
    if (!args.json.empty()) write_json_atomically(args.json, j);
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }
  return 0;
}

}  // namespace

void register_compare(CLI::App& app, CommandContext& ctx) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* sub = app.add_subcommand(
      "compare", "Error of a result A against a reference B: probes and/or surfaces.");
  sub->add_option("A", args->a, "Result: a probes.csv, or a run folder")->required();
  sub->add_option("B", args->b,
                  "Reference: a probes.csv (e.g. from 'hrad reference'), or a run folder (e.g. "
                  "a much finer 'hrad solve')")
      ->required();
  sub->add_option("--floor", args->floor,
                  "Absolute irradiance floor of the probes' relative error [default: 1e-3 x "
                  "the mean reference irradiance]")
      ->type_name("X")
      ->check(positive_number());
  sub->add_option("--samples", args->samples,
                  "Surface metric: points drawn over the reference mesh [default: 200000]")
      ->type_name("N")
      ->transform(integer_in(1, std::uint64_t{1} << 32));
  sub->add_option("--seed", args->seed, "Surface metric: seed of the sample points [default: 1]")
      ->type_name("N")
      ->transform(integer_in(0, std::numeric_limits<std::uint64_t>::max()));
  sub->add_flag("--per-probe", args->per_probe, "Print one row per probe");
  sub->add_option("--json", args->json, "Also write the numbers to FILE (JSON)")->type_name("FILE");
  sub->callback([args, &ctx] { ctx.status = run_compare(*args); });
}

}  // namespace hrad::cli

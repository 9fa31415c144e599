// Error metrics between a result and a reference (issue 7), for `hrad compare`.
//
// Probe metric. Two probes.csv files (from `hrad solve` or `hrad reference`) over the
// same probes: per probe and channel the relative error |a - r| / max(|r|, floor), the
// probe's error being its largest channel; then mean, max and RMS over the probes. The
// default floor is 1e-3 x the mean reference irradiance (over probes and channels), so a
// dark probe is judged against the scene's typical irradiance instead of its own
// near-zero value. When the reference has standard-error columns (SE_r, SE_g, SE_b, as
// `hrad reference` writes), each probe also gets z = max over channels of |a - r| / SE
// and counts as "within the reference's noise" when z <= 2.
//
// Surface metric. Two solution.ply meshes of the same scene (typically a solution and a
// much finer one as reference). Points are drawn uniformly over the reference mesh,
// stratified by its polygons (max(1, ceil(N a_i / A)) points on polygon i, each
// weighing a_i / n_i), so every input face is covered in proportion to its area. At each
// point both meshes are evaluated as render.png shows them: the polygon found by a
// short ray along the reference polygon's normal, its vertex radiosities interpolated
// (barycentric for triangles, bilinear for quads). Reported per channel and for the
// three channels together: relative L1 = sum w|a - r| / sum w|r| and relative
// L2 = sqrt(sum w (a - r)^2 / W) / (sum w|r| / W), i.e. both relative to the
// reference's area-weighted mean radiosity. Points where either mesh has no polygon
// facing the same way within 1e-4 of the scene diagonal are counted as unmatched and
// left out.
#pragma once

#include "core/base/geometry.h"
#include "core/scene/probes.h"
#include "core/scene/render_mesh.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hrad {

/// A probes.csv as read back: the probes, their irradiance and, when present, the
/// standard-error columns.
struct ProbeTable {
  std::string file;
  std::vector<Probe> probes;
  std::vector<Rgb> irradiance;
  std::vector<Rgb> std_error;  ///< empty when the file has no SE_r, SE_g, SE_b columns
};

/// Parses CSV text with header columns x,y,z,nx,ny,nz,E_r,E_g,E_b (in any order, other
/// columns ignored). Throws InputError(file, line, ...) for a missing column, a wrong
/// field count, or a field that is not a finite number.
[[nodiscard]] ProbeTable parse_probe_table(const std::string& text, const std::string& file);
/// Reads `path`, or `path`/probes.csv when `path` is a folder.
[[nodiscard]] ProbeTable read_probe_table(const std::filesystem::path& path);

struct ProbeError {
  Rgb result = Rgb::Zero(), reference = Rgb::Zero();
  double rel_error = 0;  ///< largest channel of |a - r| / max(|r|, floor)
  double z = -1;         ///< largest channel of |a - r| / SE; -1 without SE columns
  /// Signed error of the channel mean: (mean(a) - mean(r)) / max(|mean(r)|, floor).
  double signed_error = 0;
};

struct ProbeComparison {
  double floor = 0;  ///< absolute floor used
  std::vector<ProbeError> probes;
  double mean = 0, max = 0, rms = 0;  ///< of rel_error over the probes
  double median = 0;                  ///< of rel_error (mean of the middle two for even counts)
  double bias = 0;                    ///< mean of signed_error: < 0 when the result is low
  std::size_t low = 0;                ///< probes with signed_error < 0
  std::size_t worst = 0;              ///< index of the probe with the largest error
  bool has_se = false;
  std::size_t within_2se = 0;  ///< probes with z <= 2 (when has_se)
};

/// Compares `result` with `reference` probe by probe. `floor` <= 0 selects the default
/// (1e-3 x mean reference irradiance). Throws std::invalid_argument, naming both files,
/// when the probe counts differ or a probe's point or normal differs (beyond 1e-6
/// relative to the probes' extent, as 9-digit CSV round trips allow).
[[nodiscard]] ProbeComparison compare_probes(const ProbeTable& result, const ProbeTable& reference,
                                             double floor = 0);

struct SurfaceComparison {
  Rgb l1 = Rgb::Zero(), l2 = Rgb::Zero();      ///< relative, per channel
  double l1_all = 0, l2_all = 0;               ///< relative, the three channels together
  Rgb reference_mean = Rgb::Zero();            ///< area-weighted mean radiosity of the reference
  double area_result = 0, area_reference = 0;  ///< total polygon areas of the two meshes
  std::size_t samples = 0, unmatched = 0;
};

/// Compares two meshes (see the file comment) with about `samples` points from a
/// generator seeded by `seed`. Throws std::invalid_argument when a mesh is empty or the
/// total areas differ by more than 1% (not the same scene).
[[nodiscard]] SurfaceComparison compare_surfaces(const RenderMesh& result,
                                                 const RenderMesh& reference,
                                                 std::size_t samples = 200000,
                                                 std::uint64_t seed = 1);

}  // namespace hrad

// Irradiance probes: points at which a solution is sampled, for comparison with other
// programs (Radiance's rtrace -I reads the same input) and with reference solutions.
//
// Input: one probe per line, "x y z nx ny nz", separated by blanks or tabs; blank lines
// and everything from '#' to the end of a line are ignored. The normal need not be unit
// length (it is normalised) but must be non-zero. Coordinates are in scene units.
// Output: CSV with header x,y,z,nx,ny,nz,E_r,E_g,E_b; E is the irradiance (W per unit
// area) arriving at the point from the hemisphere around n; numbers printed with 9
// significant digits (%.9g).
#pragma once

#include "core/base/geometry.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace hrad {

struct Scene;

struct Probe {
  Vec3 p = Vec3::Zero();
  Vec3 n = Vec3::UnitZ();  ///< unit normal
};

/// Parses probe lines from `text`; `file` only names the source in errors. Throws
/// InputError(file, line, ...) for a wrong number of fields, a field that is not a
/// number, a non-finite number or a zero normal.
[[nodiscard]] std::vector<Probe> parse_probes(const std::string& text, const std::string& file);

/// Reads and parses a probe file. Throws InputError(path, 0, ...) when it cannot be read.
[[nodiscard]] std::vector<Probe> read_probes(const std::string& path);

/// `n` probes at points drawn uniformly by area over the scene's faces (a face with
/// probability proportional to its area, then a uniform point in it), each lifted off
/// its face by 1e-6 of the scene's bounding-box diagonal along the face's front normal,
/// which is the probe's normal. A pure function of the scene, `n` and `seed`. Points
/// on faces that see nothing (a face in contact with another) are kept: a random set
/// should not be chosen to suit the solver.
[[nodiscard]] std::vector<Probe> random_surface_probes(const Scene& scene, std::size_t n,
                                                       std::uint64_t seed);

/// Probe lines ("x y z nx ny nz", %.9g) that parse_probes reads back, with a comment
/// line first when `comment` is not empty.
[[nodiscard]] std::string probes_text(const std::vector<Probe>& probes, const std::string& comment);

/// The CSV text for probes and their irradiance (same length, else std::invalid_argument).
[[nodiscard]] std::string probes_csv(const std::vector<Probe>& probes,
                                     const std::vector<Rgb>& irradiance);

/// probes_csv written atomically.
void write_probes_csv(const std::filesystem::path& path, const std::vector<Probe>& probes,
                      const std::vector<Rgb>& irradiance);

}  // namespace hrad

// Pictures of a solution: a pinhole camera, one ray per sample against the leaf
// polygons of a RenderMesh, radiosity interpolated from the polygon's vertices.
//
// Radiometry. Surfaces are Lambertian, so the radiance leaving a point is L = B / pi
// (B: radiosity in W per unit area, L: W per steradian per unit area). Surfaces are
// shown two-sided (a radiosity mesh has no meaningful back side); the background is 0.
//
// Tone mapping (radiance -> 8-bit sRGB), in this order:
//  1. exposure k: ToneMap::exposure when > 0, otherwise automatic: k = key / L_avg where
//     L_avg is the log-average (geometric mean) luminance of the samples that show a
//     surface of positive luminance (Reinhard et al. 2002, "key value"; the geometric
//     mean keeps a small, very bright light source from darkening the whole picture);
//     then times 2^ToneMap::stops (the `exposure` option: +1 stop twice as bright).
//     Luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (linear Rec. 709 primaries).
//  2. per channel, x = k L mapped to x / (1 + x) (Reinhard) or clamped to [0, 1];
//  3. the sRGB transfer curve (IEC 61966-2-1), rounded to 8 bits.
// A scene with no positive luminance anywhere gets k = 2^stops (a black picture).
#pragma once

#include "core/scene/render_mesh.h"
#include "core/scene/scene.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace hrad {

struct ToneMap {
  double exposure = 0;   ///< multiplier on radiance; <= 0 selects the automatic exposure
  double key = 0.18;     ///< automatic exposure maps the log-average luminance to this
  bool reinhard = true;  ///< false: clamp instead of x / (1 + x)
  double stops = 0;      ///< the exposure above is multiplied by 2^stops
};

/// Memory that rendering and writing a picture take per pixel, measured: the radiance
/// and coverage buffers, the tone-mapped copy and the PNG encoder's (16384 x 12288
/// pixels: 11.8 GB). Commands refuse a size whose need is above their memory limit.
inline constexpr double kRenderBytesPerPixel = 60;

/// Rec. 709 luminance of a linear RGB triple.
[[nodiscard]] inline double luminance(const Rgb& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

/// The exposure k that `tm` applies to these radiance values (step 1 above): tm.exposure
/// if positive, else key / log-average luminance of the values with positive luminance;
/// times 2^tm.stops.
[[nodiscard]] double choose_exposure(std::span<const Rgb> radiance, const ToneMap& tm);

/// Steps 2 and 3 for one value, with the exposure already chosen.
[[nodiscard]] std::array<std::uint8_t, 3> tone_map(const Rgb& radiance, double exposure,
                                                   const ToneMap& tm);

/// A rendered picture before tone mapping. Row-major, row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> radiance;    ///< mean radiance over the pixel's samples (misses count 0)
  std::vector<float> coverage;  ///< fraction of the pixel's samples that hit a polygon
  [[nodiscard]] const Rgb& at(int x, int y) const {
    return radiance[static_cast<std::size_t>(y) * width + x];
  }
};

/// Direction of the primary ray through image point (px, py), in pixels from the top-left
/// corner (pixel centres at +0.5). Not normalised. Throws std::invalid_argument for a
/// degenerate camera (eye == target, up parallel to the view, fov outside (0, 180)).
[[nodiscard]] Vec3 camera_ray(const Camera& cam, int width, int height, double px, double py);

/// Renders radiance with supersample x supersample stratified samples per pixel (pixel
/// centres for 1). Parallel over rows with OpenMP. Throws std::invalid_argument for a
/// bad mesh, size (< 1) or supersample (< 1 or > 16).
[[nodiscard]] Image render_radiance(const RenderMesh& mesh, const Camera& cam, int width,
                                    int height, int supersample = 1);

/// The exposure tone_map_image applies: choose_exposure over the covered pixels.
[[nodiscard]] double image_exposure(const Image& img, const ToneMap& tm);

/// Tone-maps an image to 8-bit sRGB, 3 bytes per pixel, row-major from the top, with
/// the exposure of image_exposure.
[[nodiscard]] std::vector<std::uint8_t> tone_map_image(const Image& img, const ToneMap& tm);

/// Encodes 8-bit RGB rows as a PNG file in memory.
[[nodiscard]] std::string encode_png(int width, int height, std::span<const std::uint8_t> rgb);

/// tone_map_image + PNG, written atomically to `out`; returns the exposure applied.
double write_png(const Image& img, const std::filesystem::path& out, const ToneMap& tm = {});

/// render_radiance + write_png; returns the exposure applied.
double render_png(const RenderMesh& mesh, const Camera& cam, int width, int height,
                  const std::filesystem::path& out, const ToneMap& tm = {}, int supersample = 1);

}  // namespace hrad

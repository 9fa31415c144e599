// Colour conversion for the MGF reader: CIE 1931 chromaticities with a luminous
// factor, as MGF gives them (`cxy x y`, or a spectrum from `cspec` / `cct`, plus
// `rd rho` or `ed lumens`), to the linear RGB triples a Scene holds.
//
// The conversion, precisely:
//   1. xyY -> XYZ with the CIE 1931 2-degree standard observer:
//        X = x Y / y,   Z = (1 - x - y) Y / y.
//      Spectra become (x, y) through the observer table (cie_observer.h); only their
//      chromaticity counts, the luminous factor comes from rd / ed (MGF's rule).
//   2. XYZ -> linear RGB with the Rec. 709 / sRGB primaries
//        R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06)
//      but with the EQUAL-ENERGY white point E (x = y = 1/3), not D65: the RGB
//      white (1, 1, 1) is XYZ (1, 1, 1). MGF's own neutral colour is equal-energy
//      grey (the default of every colour context), and MGF measures reflectance
//      against an equal-energy source, so with white E a grey MGF colour of luminous
//      factor Y maps to R = G = B = Y. Chromaticities within kGreyTolerance of
//      (1/3, 1/3) are snapped to exact grey, so that grey scenes stay grey channel
//      for channel (Scene::is_grey) even when a file prints 0.333 0.333 or gives a
//      flat spectrum over the visible range.
//   3. No gamma: every value is linear.
// The matrix is derived at startup from the primaries and white point above (the
// standard construction: scale the primaries' XYZ so that they sum to the white).
//
// Gamut mapping (xyY_to_gamut_rgb). A colour outside the Rec. 709 triangle has a
// negative channel, and a saturated reflectance can exceed 1 in a channel. Such a
// colour c is moved along the straight line towards the grey g = (Y, Y, Y) of the
// same luminance, c' = g + t (c - g), with the largest t in [0, 1] that puts every
// channel in [0, upper] (upper = 1 for reflectance; none for emission, which only
// needs to be non-negative). Every point of that line has luminance Y, and its
// chromaticity lies on the segment from white E to (x, y), so luminance and hue
// (dominant wavelength) are kept and only saturation is lost. This is what the MGF
// reference code does for the lower bound (Radiance's cie_rgb -> clipgamut with
// CGAMUT_LOWER, black and white limits: desaturate towards the equal-luminance grey
// until no channel is negative); hrad applies the same desaturation to the upper
// bound of reflectances, which the reference leaves above 1. The old hrad clipped
// each channel to [0, 1] instead, which shifts hue and luminance.
//
// Chromaticities with y = 0 (allowed by MGF: x, y >= 0, x + y <= 1) carry no luminance:
// X = x Y / y is unbounded. hrad takes the limit y -> 0+ of the mapping above: c - g
// grows without bound in the direction u = M (x - y, 0, z - y) (zero luminance), so
// the result is g + t u with t at the first channel bound, i.e. the most saturated
// in-gamut colour of luminance Y in that direction; y > 0 colours near it map
// continuously to it. A luminous factor Y = 0 is black whatever the chromaticity.
// The result is always finite: no inf or NaN reaches a Scene.
//
// Units: rd and RGB reflectances are unitless. MGF `ed` is a luminous emittance in
// lm/m^2; Radiance's convention of 179 lm/W for "white" light turns it into a
// radiometric exitance in W/m^2: E_rgb = rgb(x, y, Y = ed / 179).
#pragma once

#include "core/base/geometry.h"

namespace hrad {

/// Radiance's luminous efficacy of equal-energy white light, in lm/W.
inline constexpr double kMgfLumensPerWatt = 179.0;
/// Chromaticities this close (in x and in y) to (1/3, 1/3) count as exact grey.
inline constexpr double kGreyTolerance = 5e-4;

/// True when (x, y) is a chromaticity MGF accepts: x >= 0, y >= 0, x + y <= 1 (the
/// MGF 1.1 parser's test); false for NaN.
bool is_mgf_chromaticity(double x, double y);

/// True when (x, y) is within kGreyTolerance of the equal-energy white (1/3, 1/3).
bool is_equal_energy_grey(double x, double y);

/// CIE 1931 xyY to linear RGB (Rec. 709 primaries, white E). Requires y > 0. Returns
/// exactly (Y, Y, Y) for a grey chromaticity; may return channels outside [0, Y] for
/// saturated colours (outside the Rec. 709 gamut or brighter than its primaries).
Rgb xyY_to_linear_rgb(double x, double y, double Y);

struct GamutRgb {
  Rgb rgb = Rgb::Zero();
  bool mapped = false;  ///< the colour was desaturated (beyond round-off) to fit
};

/// xyY to linear RGB with every channel in [0, upper], by the gamut mapping above.
/// Requires is_mgf_chromaticity(x, y) (y = 0 allowed), 0 <= Y <= upper, upper > 0
/// (+infinity for emission). Round-off (1e-9 relative) is clamped, not counted.
GamutRgb xyY_to_gamut_rgb(double x, double y, double Y, double upper);

/// The 3x3 matrix taking CIE XYZ to linear RGB (exposed for tests).
Eigen::Matrix3d xyz_to_linear_rgb_matrix();

}  // namespace hrad

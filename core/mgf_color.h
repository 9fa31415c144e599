// Colour conversion for the MGF reader: CIE 1931 chromaticities with a luminous
// factor, as MGF gives them (`cxy x y` plus `rd rho` or `ed lumens`), to the linear
// RGB triples a Scene holds.
//
// The conversion, precisely:
//   1. xyY -> XYZ with the CIE 1931 2-degree standard observer:
//        X = x Y / y,   Z = (1 - x - y) Y / y.
//   2. XYZ -> linear RGB with the Rec. 709 / sRGB primaries
//        R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06)
//      but with the EQUAL-ENERGY white point E (x = y = 1/3), not D65: the RGB
//      white (1, 1, 1) is XYZ (1, 1, 1). MGF's own neutral colour is equal-energy
//      grey (the default of every colour context), and MGF measures reflectance
//      against an equal-energy source, so with white E a grey MGF colour of luminous
//      factor Y maps to R = G = B = Y. Chromaticities within kGreyTolerance of
//      (1/3, 1/3) are snapped to exact grey, so that grey scenes stay grey channel
//      for channel (Scene::is_grey) even when a file prints 0.333 0.333.
//   3. No gamma: every value is linear.
// The matrix is derived at startup from the primaries and white point above (the
// standard construction: scale the primaries' XYZ so that they sum to the white).
//
// Units: rd and RGB reflectances are unitless. MGF `ed` is a luminous emittance in
// lm/m^2; Radiance's convention of 179 lm/W for "white" light turns it into a
// radiometric exitance in W/m^2: E_rgb = ed / 179 * rgb(x, y, Y = 1).
#pragma once

#include "core/geometry.h"

namespace hrad {

/// Radiance's luminous efficacy of equal-energy white light, in lm/W.
inline constexpr double kMgfLumensPerWatt = 179.0;
/// Chromaticities this close (in x and in y) to (1/3, 1/3) count as exact grey.
inline constexpr double kGreyTolerance = 5e-4;

/// True when (x, y) is within kGreyTolerance of the equal-energy white (1/3, 1/3).
bool is_equal_energy_grey(double x, double y);

/// CIE 1931 xyY to linear RGB (Rec. 709 primaries, white E). Requires y > 0. Returns
/// exactly (Y, Y, Y) for a grey chromaticity; may return channels outside [0, Y] for
/// saturated colours (outside the Rec. 709 gamut or brighter than its primaries).
Rgb xyY_to_linear_rgb(double x, double y, double Y);

/// The 3x3 matrix taking CIE XYZ to linear RGB (exposed for tests).
Eigen::Matrix3d xyz_to_linear_rgb_matrix();

}  // namespace hrad

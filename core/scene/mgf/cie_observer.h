// The CIE 1931 2-degree standard colorimetric observer, and spectra -> CIE XYZ.
//
// The colour-matching functions xbar, ybar, zbar are the CIE's 5 nm table from 360 to
// 830 nm (CIE 15:2004, table T.4; the same values as the CVRL file ciexyz31.txt), taken
// to be linear between the table's wavelengths and zero outside 360..830 nm.
//
// A sampled spectrum S (MGF `cspec lo hi v1 .. vN`: N >= 2 values evenly spaced from
// lo to hi nm) is linear between its samples and zero outside [lo, hi]. Its XYZ is
//   X = integral of S(l) xbar(l) dl over 360..830 nm (Y, Z likewise),
// integrated exactly: both factors are piecewise linear, so on each interval between
// consecutive breakpoints (the table's and the samples' wavelengths) the product is a
// quadratic and Simpson's rule is exact. Narrow spikes (a spectrum 2 nm wide) and
// spectra sampled finer than the table are therefore integrated without resampling.
// Units: those of S times nm; only ratios (chromaticities) are used by the MGF reader.
#pragma once

#include <Eigen/Core>

#include <span>

namespace hrad {

/// Shortest and longest wavelength of the observer table, and its step (nm).
inline constexpr double kCieFirstNm = 360.0;
inline constexpr double kCieLastNm = 830.0;
inline constexpr double kCieStepNm = 5.0;

/// (xbar, ybar, zbar) at `nm`: the table linearly interpolated; zero outside
/// [kCieFirstNm, kCieLastNm].
Eigen::Vector3d cie1931_cmf(double nm);

/// CIE XYZ of the spectrum `values` (at least 2) evenly spaced from `lo_nm` to
/// `hi_nm` (lo_nm < hi_nm), as described above. Values may be any finite numbers; the
/// MGF reader passes only non-negative ones.
Eigen::Vector3d spectrum_to_xyz(double lo_nm, double hi_nm, std::span<const double> values);

/// Planck's law: the spectral radiant exitance of a black body at `kelvin` (> 0) at
/// wavelength `nm`, in W m^-2 per nm. c1 = 2 pi h c^2 and c2 = h c / k from the exact
/// SI values of h, c and k (c2 = 1.438777e-2 m K).
double planck_exitance(double nm, double kelvin);

/// CIE XYZ of a black body at `kelvin` (> 0): Planck's law sampled at the table's 95
/// wavelengths and integrated as a spectrum from 360 to 830 nm (spectrum_to_xyz).
Eigen::Vector3d blackbody_xyz(double kelvin);

}  // namespace hrad

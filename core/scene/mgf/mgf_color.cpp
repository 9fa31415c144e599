// CIE xyY -> linear RGB (Rec. 709 primaries, equal-energy white) and the gamut
// mapping towards equal-luminance grey; see mgf_color.h.
#include "core/scene/mgf/mgf_color.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hrad {

namespace {

Eigen::Matrix3d make_xyz_to_rgb() {
  // Columns: XYZ of each primary with Y = 1, i.e. (x/y, 1, (1-x-y)/y).
  const double prim[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
  Eigen::Matrix3d p;
  for (int c = 0; c < 3; ++c) {
    const double x = prim[c][0], y = prim[c][1];
    p.col(c) = Eigen::Vector3d(x / y, 1.0, (1.0 - x - y) / y);
  }
  // Scale each primary so that RGB (1,1,1) is the white point E: XYZ (1,1,1).
  const Eigen::Vector3d s = p.partialPivLu().solve(Eigen::Vector3d::Ones());
  const Eigen::Matrix3d rgb_to_xyz = p * s.asDiagonal();
  return rgb_to_xyz.inverse();
}

// Relative size of round-off that is clamped silently (a primary's other channels
// come out as +-1e-17, not 0).
constexpr double kRoundOff = 1e-9;

}  // namespace

Eigen::Matrix3d xyz_to_linear_rgb_matrix() {
  static const Eigen::Matrix3d m = make_xyz_to_rgb();
  return m;
}

bool is_mgf_chromaticity(double x, double y) { return x >= 0 && y >= 0 && x + y <= 1; }

bool is_equal_energy_grey(double x, double y) {
  return std::abs(x - 1.0 / 3.0) <= kGreyTolerance && std::abs(y - 1.0 / 3.0) <= kGreyTolerance;
}

Rgb xyY_to_linear_rgb(double x, double y, double Y) {
  if (is_equal_energy_grey(x, y)) return Rgb::Constant(Y);
  const Eigen::Vector3d xyz(x * Y / y, Y, (1.0 - x - y) * Y / y);
  return (xyz_to_linear_rgb_matrix() * xyz).array();
}

GamutRgb xyY_to_gamut_rgb(double x, double y, double Y, double upper) {
  if (!(Y > 0)) return {};
  if (is_equal_energy_grey(x, y)) return {Rgb::Constant(Y), false};
  if (y > 0) {
    const Rgb c = xyY_to_linear_rgb(x, y, Y);
    const double tol = kRoundOff * c.abs().maxCoeff();
    if (c.allFinite() && (c >= -tol).all() && (c <= upper + kRoundOff * upper).all())
      return {c.max(0.0).min(upper), false};
  }
  // c - g = (Y / y) u with u = M (x - y, 0, z - y): finite, of zero luminance, and
  // defined for y = 0 too (where Y / y is infinite).
  const double z = 1.0 - x - y;
  const Eigen::Vector3d u = xyz_to_linear_rgb_matrix() * Eigen::Vector3d(x - y, 0.0, z - y);
  double s = y > 0 ? Y / y : std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (u[i] < 0)
      s = std::min(s, Y / -u[i]);
    else if (u[i] > 0)
      s = std::min(s, (upper - Y) / u[i]);  // +inf for emission
  }
  const Rgb out = (Rgb::Constant(Y) + s * u.array()).max(0.0).min(upper);
  return {out, true};
}

}  // namespace hrad

// CIE xyY -> linear RGB (Rec. 709 primaries, equal-energy white); see mgf_color.h.
#include "core/mgf_color.h"

#include <Eigen/LU>

#include <cmath>

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

}  // namespace

Eigen::Matrix3d xyz_to_linear_rgb_matrix() {
  static const Eigen::Matrix3d m = make_xyz_to_rgb();
  return m;
}

bool is_equal_energy_grey(double x, double y) {
  return std::abs(x - 1.0 / 3.0) <= kGreyTolerance && std::abs(y - 1.0 / 3.0) <= kGreyTolerance;
}

Rgb xyY_to_linear_rgb(double x, double y, double Y) {
  if (is_equal_energy_grey(x, y)) return Rgb::Constant(Y);
  const Eigen::Vector3d xyz(x * Y / y, Y, (1.0 - x - y) * Y / y);
  return (xyz_to_linear_rgb_matrix() * xyz).array();
}

}  // namespace hrad

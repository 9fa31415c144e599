#include "core/scene/mgf/cie_observer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hrad {
namespace {

Eigen::Vector2d xy(const Eigen::Vector3d& xyz) { return xyz.head<2>() / xyz.sum(); }

TEST(CieObserver, TableGivesThePublishedSpectralLocus) {
  // CIE 15:2004 spectral locus chromaticities (x, y), 4-5 decimals: a transcription
  // check of three rows of the table.
  struct Point {
    double nm, x, y;
  };
  for (const Point p :
       {Point{450, 0.15664, 0.01771}, Point{550, 0.30160, 0.69231}, Point{600, 0.62704, 0.37249}}) {
    const Eigen::Vector2d c = xy(cie1931_cmf(p.nm));
    EXPECT_NEAR(c.x(), p.x, 1e-5) << p.nm;
    EXPECT_NEAR(c.y(), p.y, 1e-5) << p.nm;
  }
  EXPECT_EQ(cie1931_cmf(555).y(), 1.0);  // the photopic peak
  EXPECT_EQ(cie1931_cmf(359.9).sum(), 0.0);
  EXPECT_EQ(cie1931_cmf(830.1).sum(), 0.0);
  // Linear between rows: halfway between 550 and 555.
  EXPECT_NEAR(cie1931_cmf(552.5).x(), 0.5 * (0.4334499 + 0.5120501), 1e-15);
}

TEST(CieObserver, EqualEnergySpectrumIsWhiteE) {
  // A flat spectrum over the table is the equal-energy white up to the table's own
  // rounding: trapezoid sums of the 5 nm table (computed by hand) give
  // (0.333315, 0.333289) for 360-830 nm and (0.333344, 0.333351) for 380-780 nm.
  const std::vector<double> flat{1, 1};
  Eigen::Vector2d c = xy(spectrum_to_xyz(360, 830, flat));
  EXPECT_NEAR(c.x(), 0.333315, 2e-6);
  EXPECT_NEAR(c.y(), 0.333289, 2e-6);
  c = xy(spectrum_to_xyz(380, 780, flat));
  EXPECT_NEAR(c.x(), 0.333344, 2e-6);
  EXPECT_NEAR(c.y(), 0.333351, 2e-6);
  // A flat 400-500 nm spectrum: trapezoid sum of the table, X 17.731925 Y 7.28344
  // Z 101.861876 (nm units).
  const Eigen::Vector3d blue = spectrum_to_xyz(400, 500, flat);
  EXPECT_NEAR(blue.x(), 17.731925, 1e-6);
  EXPECT_NEAR(blue.y(), 7.28344, 1e-6);
  EXPECT_NEAR(blue.z(), 101.861876, 1e-6);
}

TEST(CieObserver, IntegrationIsExactForPiecewiseLinearSpectra) {
  // The same straight line sampled by 2, 3, 48 and 1001 values: one XYZ.
  const auto ramp = [](int n) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) v[i] = 1.0 + 2.0 * i / (n - 1);
    return v;
  };
  const Eigen::Vector3d ref = spectrum_to_xyz(380, 730, ramp(2));
  for (int n : {3, 48, 1001}) {
    const Eigen::Vector3d x = spectrum_to_xyz(380, 730, ramp(n));
    EXPECT_NEAR((x - ref).norm(), 0.0, 1e-11 * ref.norm()) << n;
  }
  // Zero outside the table; a range straddling its ends counts only the inside.
  EXPECT_EQ(spectrum_to_xyz(200, 359, std::vector<double>{1, 1}).sum(), 0.0);
  EXPECT_EQ(spectrum_to_xyz(831, 1000, std::vector<double>{1, 1}).sum(), 0.0);
  const Eigen::Vector3d wide = spectrum_to_xyz(300, 900, std::vector<double>{1, 1, 1, 1, 1, 1, 1});
  const Eigen::Vector3d table = spectrum_to_xyz(360, 830, std::vector<double>{1, 1});
  EXPECT_NEAR((wide - table).norm(), 0.0, 1e-12 * table.norm());
}

TEST(CieObserver, NarrowSpikeIsTheSpectralLocus) {
  // A triangle of half-width h at 550 nm integrates against the CMF, which has a kink
  // there, to h cmf(550) + h^2 (s_right - s_left) / 6 (s: the slopes either side):
  // a relative change of about 4e-4 h in xbar, which moves (x, y) by about 2e-4 h.
  // h = 0.01 nm: the table row itself, the published locus point (0.30160, 0.69231).
  Eigen::Vector2d c = xy(spectrum_to_xyz(549.99, 550.01, std::vector<double>{0, 1, 0}));
  EXPECT_NEAR(c.x(), 0.30160, 1e-5);
  EXPECT_NEAR(c.y(), 0.69231, 1e-5);
  // h = 1 nm (whole nanometres, as the MGF 1.1 parser wants): within 3e-4.
  c = xy(spectrum_to_xyz(549, 551, std::vector<double>{0, 1, 0}));
  EXPECT_NEAR(c.x(), 0.30160, 3e-4);
  EXPECT_NEAR(c.y(), 0.69231, 3e-4);
  // An off-grid spike at 452.5 nm: between the 450 and 455 rows.
  const Eigen::Vector3d s = spectrum_to_xyz(452.4, 452.6, std::vector<double>{0, 1, 0});
  const Eigen::Vector3d mid = 0.5 * (cie1931_cmf(450) + cie1931_cmf(455));
  EXPECT_NEAR((s / s.y() - mid / mid.y()).norm(), 0.0, 1e-9);
}

TEST(CieObserver, BlackBodyChromaticities) {
  // CIE illuminant A is a Planckian radiator at 2856 K (c2 = 1.4388e-2 m K):
  // published (0.44757, 0.40745).
  Eigen::Vector2d c = xy(blackbody_xyz(2856));
  EXPECT_NEAR(c.x(), 0.44757, 1e-4);
  EXPECT_NEAR(c.y(), 0.40745, 1e-4);
  // 6504 K against the Planckian locus approximation of Kim et al. (2002),
  // (0.313432, 0.323602). It is NOT D65 (0.3127, 0.3290): D65 has a correlated colour
  // temperature of 6504 K but lies 0.005 above the Planckian locus in y.
  c = xy(blackbody_xyz(6504));
  EXPECT_NEAR(c.x(), 0.313432, 2e-4);
  EXPECT_NEAR(c.y(), 0.323602, 2e-4);
  EXPECT_GT(0.3290 - c.y(), 0.004);
  // 1000 K: (0.6528, 0.3444) in Wyszecki & Stiles' Planckian locus table.
  c = xy(blackbody_xyz(1000));
  EXPECT_NEAR(c.x(), 0.6528, 2e-4);
  EXPECT_NEAR(c.y(), 0.3444, 2e-4);
  // Very hot: the Rayleigh-Jeans limit, finite.
  EXPECT_TRUE(blackbody_xyz(1e12).allFinite());
  EXPECT_GT(blackbody_xyz(1e12).sum(), 0.0);
}

TEST(CieObserver, PlanckPeaksAtWiensWavelength) {
  // Wien's displacement law, b = 2.897771955e-3 m K: at 5000 K the exitance peaks at
  // 579.554 nm.
  const double peak = 2.897771955e-3 / 5000 * 1e9;
  const double at = planck_exitance(peak, 5000);
  EXPECT_GT(at, planck_exitance(peak - 0.5, 5000));
  EXPECT_GT(at, planck_exitance(peak + 0.5, 5000));
  // Units (W m^-2 per nm): c1 / (l^5 (exp(c2 / l T) - 1)) at 500 nm, 5000 K.
  const double l = 500e-9, c1 = 3.741771852e-16, c2 = 1.438776877e-2;
  EXPECT_NEAR(planck_exitance(500, 5000),
              c1 / (std::pow(l, 5) * std::expm1(c2 / (l * 5000))) * 1e-9,
              1e-8 * planck_exitance(500, 5000));
}

}  // namespace
}  // namespace hrad

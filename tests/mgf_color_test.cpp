// MGF colour entities through the reader: boundary chromaticities, spectra (cspec,
// cct), cmix, gamut mapping, and the ies rule. Expected RGB values were computed by
// hand (exact rational arithmetic for the Rec. 709 / white E matrix, trapezoid sums of
// the CIE 5 nm table), independently of hrad's code.
#include "core/scene/mgf/mgf_color.h"
#include "core/base/input_error.h"
#include "core/scene/mgf/mgf_reader.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <map>
#include <string>

namespace hrad {
namespace {

const std::string kTri = "v a =\n p 0 0 0\nv b =\n p 1 0 0\nv d =\n p 0 1 0\nf a b d\n";

// The one material of "m x =\n c\n <colour>\n <rest>" around a triangle.
Material material_of(const std::string& colour, const std::string& rest) {
  const Scene s = parse_mgf("m x =\n c\n " + colour + "\n " + rest + "\n" + kTri, "t.mgf");
  EXPECT_EQ(s.materials.size(), 1u);
  return s.materials.at(0);
}

Scene scene_of(const std::string& colour, const std::string& rest) {
  return parse_mgf("m x =\n c\n " + colour + "\n " + rest + "\n" + kTri, "t.mgf");
}

// (Colour warnings all say "colour"; "no face emits light" does not.)
bool has_warning(const Scene& s, const std::string& fragment) {
  for (const auto& w : s.warnings)
    if (w.find(fragment) != std::string::npos) return true;
  return false;
}

void expect_rgb(const Rgb& got, double r, double g, double b, double tol, const std::string& what) {
  EXPECT_NEAR(got[0], r, tol) << what;
  EXPECT_NEAR(got[1], g, tol) << what;
  EXPECT_NEAR(got[2], b, tol) << what;
}

// Luminance Y of a linear RGB triple (the Y row of RGB -> XYZ).
double luminance(const Rgb& c) {
  const Eigen::Matrix3d to_xyz = xyz_to_linear_rgb_matrix().inverse();
  return (to_xyz * c.matrix()).y();
}

// Chromaticity of a linear RGB triple.
Eigen::Vector2d chromaticity(const Rgb& c) {
  const Eigen::Vector3d xyz = xyz_to_linear_rgb_matrix().inverse() * c.matrix();
  return xyz.head<2>() / xyz.sum();
}

// Line `line` of `text` holds the error, and its message holds `fragment`.
void expect_error(const std::string& text, int line, const std::string& fragment) {
  try {
    parse_mgf(text, "t.mgf");
    ADD_FAILURE() << "no InputError for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "t.mgf");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// ---- cxy on the edges of the chromaticity triangle -------------------------

TEST(MgfCxy, BoundaryChromaticitiesAreAccepted) {
  // The MGF 1.1 parser accepts x >= 0, y >= 0, x + y <= 1. Each of these is outside
  // the Rec. 709 gamut; rd 0.5 keeps luminance 0.5 after the mapping.
  struct Case {
    const char* cxy;
    double r, g, b;
  };
  for (const Case c : {Case{"cxy 0 0.2", 0.0, 0.646726370, 0.936090226},
                       Case{"cxy 0 0.38", 0.0, 0.677869466, 0.614108743},
                       Case{"cxy 0.5 0.5", 0.677858439, 0.481164419, 0.0},
                       Case{"cxy 0.4 0", 1.0, 0.268875839, 0.936479592},
                       Case{"cxy 0 0", 0.322141561, 0.518835581, 1.0}}) {
    const Scene s = scene_of(c.cxy, "rd 0.5");
    const Rgb& r = s.materials.at(0).reflectance;
    EXPECT_TRUE(r.allFinite()) << c.cxy;
    expect_rgb(r, c.r, c.g, c.b, 1e-8, c.cxy);
    EXPECT_NEAR(luminance(r), 0.5, 1e-12) << c.cxy;
    EXPECT_TRUE(has_warning(s, "1 colour(s) outside the RGB gamut (1 reflectance, 0 emission)"))
        << c.cxy;
  }
}

TEST(MgfCxy, OutsideTheTriangleIsRejectedWithItsLine) {
  const std::string pre = "m x =\n c\n";  // the cxy is on line 3
  expect_error(pre + " cxy -0.01 0.3\n" + kTri, 3, "need x >= 0, y >= 0, x + y <= 1");
  expect_error(pre + " cxy 0.3 -1e-9\n" + kTri, 3, "is not a chromaticity");
  expect_error(pre + " cxy 0.6 0.41\n" + kTri, 3, "is not a chromaticity");
  expect_error(pre + " cxy 1 1e-12\n" + kTri, 3, "is not a chromaticity");
  expect_error(pre + " cxy nan 0.3\n" + kTri, 3, "not a finite number");
  expect_error(pre + " cxy 0.3 inf\n" + kTri, 3, "not a finite number");
  // The corners themselves are chromaticities.
  EXPECT_NO_THROW(parse_mgf(pre + " cxy 1 0\n rd 0.2\n" + kTri, "t.mgf"));
  EXPECT_NO_THROW(parse_mgf(pre + " cxy 0 1\n rd 0.2\n" + kTri, "t.mgf"));
}

TEST(MgfCxy, ZeroLuminanceChromaticities) {
  // y = 0: the limit y -> 0+ of the mapping, finite, luminance kept. Emission has no
  // upper bound: cxy 0 0 with ed 179 (Y = 1) is (0, 1.105902, 3.811224).
  Material m = material_of("cxy 0 0", "ed 179");
  expect_rgb(m.emission, 0.0, 1.105902092, 3.81122449, 1e-8, "cxy 0 0, ed 179");
  EXPECT_NEAR(luminance(m.emission), 1.0, 1e-12);
  m = material_of("cxy 0.4 0", "ed 358");
  expect_rgb(m.emission, 2 * 3.163339383, 0.0, 2 * 2.888506982, 2e-8, "cxy 0.4 0, ed 358");
  // Continuous in y: y = 1e-9 maps to (almost) the same colour as y = 0.
  const Material near = material_of("cxy 0.4 1e-9", "rd 0.5");
  const Material at = material_of("cxy 0.4 0", "rd 0.5");
  EXPECT_NEAR((near.reflectance - at.reflectance).abs().maxCoeff(), 0.0, 1e-8);
  // No luminance, no light, whatever the chromaticity.
  m = material_of("cxy 0 0", "rd 0");
  EXPECT_EQ(m.reflectance.abs().maxCoeff(), 0.0);
  EXPECT_FALSE(has_warning(scene_of("cxy 0.4 0", "rd 0\n ed 0"), "colour"));
}

// ---- gamut mapping ----------------------------------------------------------

TEST(MgfGamut, DesaturatesTowardsEqualLuminanceGrey) {
  // Magenta (0.4, 0.15) at rd 0.3: raw RGB (1.396552, -0.184761, 1.028571). Clipping
  // per channel gave (1, 0, 1) (luminance 0.322, hue shifted to pinkish purple); the
  // mapping keeps luminance 0.3 and the hue line: (0.978614, 0, 0.750885).
  Material m = material_of("cxy 0.4 0.15", "rd 0.3");
  expect_rgb(m.reflectance, 0.978613613, 0.0, 0.750884786, 1e-8, "magenta");
  EXPECT_NEAR(luminance(m.reflectance), 0.3, 1e-12);
  // Its chromaticity lies on the segment from white E to (0.4, 0.15).
  const Eigen::Vector2d c = chromaticity(m.reflectance) - Eigen::Vector2d(1, 1) / 3.0;
  const Eigen::Vector2d d = Eigen::Vector2d(0.4, 0.15) - Eigen::Vector2d(1, 1) / 3.0;
  EXPECT_NEAR(c.x() * d.y() - c.y() * d.x(), 0.0, 1e-12);
  EXPECT_GT(c.dot(d), 0.0);
  EXPECT_LT(c.norm(), d.norm());
  // The red primary at rd 0.5 is (1.951, 0, 0) raw: above 1, so desaturated until R = 1.
  m = material_of("cxy 0.64 0.33", "rd 0.5");
  expect_rgb(m.reflectance, 1.0, 0.32775378, 0.32775378, 1e-8, "red");
  // rd 1 with any colour is white: the only reflectance of luminance 1.
  m = material_of("cxy 0.64 0.33", "rd 1");
  expect_rgb(m.reflectance, 1.0, 1.0, 1.0, 1e-12, "red, rd 1");
  // Emission is only made non-negative: (0.5, 0.5) at Y = 1 is (1.355717, 0.962329, 0).
  m = material_of("cxy 0.5 0.5", "ed 179");
  expect_rgb(m.emission, 1.355716878, 0.962328838, 0.0, 1e-8, "yellow emitter");
}

TEST(MgfGamut, OneWarningCountsTheMappedColours) {
  // Two mapped reflectances, one mapped emission, one in-gamut colour, one material
  // reused: "3 colour(s) ... (2 reflectance, 1 emission)".
  const Scene s =
      parse_mgf("m a =\n c\n cxy 0.4 0.15\n rd 0.3\n" + kTri +
                    "m b =\n c\n cxy 0.64 0.33\n rd 0.5\n c\n cxy 0 0.2\n ed 100\n" + kTri +
                    "m d =\n c\n cxy 0.4 0.35\n rd 0.2\n" + kTri + "m a\n" + kTri,
                "t.mgf");
  int count = 0;
  for (const auto& w : s.warnings) count += w.find("outside the RGB gamut") != std::string::npos;
  EXPECT_EQ(count, 1);
  EXPECT_TRUE(has_warning(s, "3 colour(s) outside the RGB gamut (2 reflectance, 1 emission)"));
  // In-gamut colours are converted exactly as before (no mapping, no warning).
  const Scene in = scene_of("cxy 0.4 0.35", "rd 0.2");
  expect_rgb(in.materials[0].reflectance, 0.2 * 1.502463054, 0.2 * 0.841464102, 0.2 * 0.67638484,
             1e-8, "in gamut");
  EXPECT_FALSE(has_warning(in, "colour"));
}

TEST(MgfGamut, DirectMappingMatchesTheRawConversionInsideTheGamut) {
  const GamutRgb g = xyY_to_gamut_rgb(0.4, 0.35, 0.25, 1.0);
  EXPECT_FALSE(g.mapped);
  const Rgb raw = xyY_to_linear_rgb(0.4, 0.35, 0.25);
  EXPECT_EQ((g.rgb - raw).abs().maxCoeff(), 0.0);
  // A primary's other channels are round-off (1e-17), clamped and not counted.
  const GamutRgb red = xyY_to_gamut_rgb(0.64, 0.33, 0.2, 1.0);
  EXPECT_FALSE(red.mapped);
  EXPECT_GE(red.rgb.minCoeff(), 0.0);
  // Grey stays exactly grey; Y = 0 is black and unmapped.
  EXPECT_EQ(xyY_to_gamut_rgb(1.0 / 3, 1.0 / 3, 0.7, 1.0).rgb[2], 0.7);
  EXPECT_FALSE(xyY_to_gamut_rgb(0, 0, 0, 1.0).mapped);
}

// ---- cspec and cct ----------------------------------------------------------

TEST(MgfSpectra, FlatSpectrumIsExactlyGrey) {
  for (const char* spec :
       {"cspec 380 780 1 1", "cspec 360 830 5 5 5 5", "cspec 300 900 2 2 2 2 2 2 2"}) {
    const Scene s = scene_of(spec, "rd 0.37");
    const Rgb& r = s.materials[0].reflectance;
    EXPECT_EQ(r[0], 0.37) << spec;
    EXPECT_EQ(r[1], 0.37) << spec;
    EXPECT_EQ(r[2], 0.37) << spec;
    EXPECT_TRUE(s.is_grey()) << spec;
    EXPECT_FALSE(has_warning(s, "colour")) << spec;
  }
  // Flat over 400-700 nm only is not E: (0.33338, 0.33405), 7e-4 from grey in y.
  const Scene s = scene_of("cspec 400 700 1 1", "rd 0.37");
  EXPECT_FALSE(s.is_grey());
}

TEST(MgfSpectra, SpikeIsTheSpectralLocusPoint) {
  // A 2 nm spike at 550 nm is the published locus point (0.30160, 0.69231), outside
  // the gamut: it maps exactly as that cxy does.
  const Material spike = material_of("cspec 549 551 0 1 0", "rd 0.5");
  const Material locus = material_of("cxy 0.30160 0.69231", "rd 0.5");
  EXPECT_NEAR((spike.reflectance - locus.reflectance).abs().maxCoeff(), 0.0, 2e-3);
  expect_rgb(spike.reflectance, 0.0336, 0.7246, 0.0, 2e-3, "550 nm spike");
  // Values between samples are linear: 540..560 at 10 nm with the peak at 550.
  const Material coarse = material_of("cspec 540 560 0 1 0", "rd 0.5");
  EXPECT_NEAR((coarse.reflectance - locus.reflectance).abs().maxCoeff(), 0.0, 2e-2);
}

TEST(MgfSpectra, CctIsAPlanckianRadiator) {
  // Illuminant A (Planckian, 2856 K): published (0.44757, 0.40745); in gamut, so the
  // emitted RGB gives the chromaticity back.
  Material m = material_of("cct 2856", "ed 179");
  Eigen::Vector2d c = chromaticity(m.emission);
  EXPECT_NEAR(c.x(), 0.44757, 1e-4);
  EXPECT_NEAR(c.y(), 0.40745, 1e-4);
  EXPECT_NEAR(luminance(m.emission), 1.0, 1e-12);
  // 6504 K: the Planckian locus (Kim et al. 2002: 0.313432, 0.323602), not D65.
  m = material_of("cct 6504", "ed 179");
  c = chromaticity(m.emission);
  EXPECT_NEAR(c.x(), 0.313432, 2e-4);
  EXPECT_NEAR(c.y(), 0.323602, 2e-4);
  EXPECT_FALSE(has_warning(scene_of("cct 3000", "ed 100"), "colour"));
}

TEST(MgfSpectra, CmixOfSpectraWeighsByLuminance) {
  // Flat 400-500 nm: XYZ (17.731925, 7.28344, 101.861876); flat 550-650 nm:
  // (76.867875, 60.846875, 0.141025) (trapezoid sums of the table). "cmix 1 a 2 b" adds
  // them at luminances 1 and 2: chromaticity (0.226008, 0.136667).
  const std::string defs =
      "c a =\n cspec 400 500 1 1\nc b =\n cspec 550 650 3 3 3\nm x =\n c m =\n cmix 1 a 2 b\n";
  const Scene mix = parse_mgf(defs + " ed 179\n" + kTri, "t.mgf");
  const Material ref = material_of("cxy 0.226008366 0.136666807", "ed 179");
  EXPECT_NEAR((mix.materials[0].emission - ref.emission).abs().maxCoeff(), 0.0, 1e-6);
  // Mixing with a y = 0 colour gives that colour (its XYZ per unit luminance is
  // unbounded); two of them mix by weight in (x, y, z): 1 (0.4, 0, 0.6) + 3 (0, 0, 1).
  const std::string zero = "c g =\nc p =\n cxy 0.4 0\nc q =\n cxy 0 0\nm x =\n c m =\n";
  Scene s = parse_mgf(zero + " cmix 1 g 1 p\n rd 0.5\n" + kTri, "t.mgf");
  EXPECT_NEAR((s.materials[0].reflectance - material_of("cxy 0.4 0", "rd 0.5").reflectance)
                  .abs()
                  .maxCoeff(),
              0.0, 1e-12);
  s = parse_mgf(zero + " cmix 1 p 3 q\n rd 0.5\n" + kTri, "t.mgf");
  EXPECT_NEAR((s.materials[0].reflectance - material_of("cxy 0.1 0", "rd 0.5").reflectance)
                  .abs()
                  .maxCoeff(),
              0.0, 1e-12);
  // A zero weight drops its colour, y = 0 or not.
  s = parse_mgf(zero + " cmix 1 g 0 p\n rd 0.5\n" + kTri, "t.mgf");
  EXPECT_TRUE(s.is_grey());
}

TEST(MgfSpectra, SmallNegativeSamplesAreTakenAsZeroWithOneWarning) {
  // Measured spectra carry noise around zero: a negative sample no larger than the
  // peak is read as 0, exactly as if the file said 0, and the file's first such
  // place is named once, with the count over all spectra.
  const std::string pre = "m x =\n c\n";
  const Scene clamped =
      parse_mgf(pre + " cspec 400 700 1 -0.5 1\n rd 0.5\nm y =\n c\n cspec 400 700 2 1 -0.1\n" +
                    " rd 0.5\n" + kTri,
                "t.mgf");
  const Scene zeros = parse_mgf(
      pre + " cspec 400 700 1 0 1\n rd 0.5\nm y =\n c\n cspec 400 700 2 1 0\n rd 0.5\n" + kTri,
      "t.mgf");
  ASSERT_EQ(clamped.materials.size(), zeros.materials.size());
  for (std::size_t i = 0; i < clamped.materials.size(); ++i)
    EXPECT_EQ((clamped.materials[i].reflectance - zeros.materials[i].reflectance).abs().maxCoeff(),
              0.0);
  std::size_t warned = 0;
  for (const std::string& w : clamped.warnings)
    if (w.find("negative cspec") != std::string::npos) {
      ++warned;
      EXPECT_NE(w.find("t.mgf:3: 2 small negative cspec value(s) taken as zero"), std::string::npos)
          << w;
    }
  EXPECT_EQ(warned, 1u);
  for (const std::string& w : zeros.warnings) EXPECT_EQ(w.find("negative"), std::string::npos);
}

TEST(MgfSpectra, BadSpectraNameTheirLine) {
  const std::string pre = "m x =\n c\n";  // the colour is on line 3
  expect_error(pre + " cspec 400 700 1\n" + kTri, 3, "at least 2 values");
  expect_error(pre + " cspec 700 400 1 1\n" + kTri, 3, "need 0 < l_min < l_max");
  expect_error(pre + " cspec 500 500 1 1\n" + kTri, 3, "need 0 < l_min < l_max");
  expect_error(pre + " cspec 0 500 1 1\n" + kTri, 3, "need 0 < l_min < l_max");
  expect_error(pre + " cspec 400 700 1 -1.5 1\n" + kTri, 3,
               "value 2 (-1.5) is negative and larger in magnitude than the spectrum's largest");
  expect_error(pre + " cspec 400 700 -1 -0.5 0\n" + kTri, 3, "value 1 (-1) is negative");
  expect_error(pre + " cspec 400 700 0 0 0\n" + kTri, 3, "no power between 360 and 830 nm");
  expect_error(pre + " cspec 900 1000 1 1\n" + kTri, 3, "no power between 360 and 830 nm");
  expect_error(pre + " cspec 400 700 1 x\n" + kTri, 3, "'x' is not a number");
  expect_error(pre + " cspec 400 700 1e307 1e307 1e307\n" + kTri, 3, "CIE XYZ overflows");
  expect_error(pre + " cct 999\n" + kTri, 3, "below 1000 K");
  expect_error(pre + " cct -3000\n" + kTri, 3, "below 1000 K");
  expect_error(pre + " cct nan\n" + kTri, 3, "not a finite number");
  expect_error(pre + " cct 3000 4000\n" + kTri, 3, "expected 1 argument(s)");
}

// ---- ies ---------------------------------------------------------------------

TEST(MgfIes, GoniometricLuminairesAreRejected) {
  // hrad's emitters are ideal diffuse: an IES photometric file cannot be represented,
  // so `ies` (with or without a transform) is an error at its line.
  expect_error("m x =\n rd 0.5\n" + kTri + "ies lamp.ies -t 0 0 3\n", 10,
               "goniometric (IES LM-63) luminaires are not supported");
  expect_error("ies\n", 1, "goniometric");
}

// ---- a file with every colour entity ------------------------------------------

TEST(MgfFiles, ColoursFile) {
  const Scene s = read_mgf(std::string(HRAD_SOURCE_DIR) + "/tests/data/mgf/colours.mgf");
  ASSERT_EQ(s.faces.size(), 9u);
  EXPECT_EQ(s.emitter_count(), 2u);
  // Every reflectance keeps its rd as luminance; every emission its ed / 179.
  const std::map<std::string, double> rd = {{"wall", 0.5},  {"floor", 0.321}, {"grey", 0.6},
                                            {"green", 0.4}, {"mixed", 0.3},   {"dark", 0.2},
                                            {"light", 0.0}, {"glow", 0.1},    {"yellow", 0.5}};
  const std::map<std::string, double> ed = {{"light", 1500 / 179.0}, {"glow", 50 / 179.0}};
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const Material& m = s.face_material(f);
    ASSERT_TRUE(rd.count(m.name)) << m.name;
    EXPECT_TRUE(m.reflectance.allFinite() && m.emission.allFinite()) << m.name;
    EXPECT_GE(m.reflectance.minCoeff(), 0.0) << m.name;
    EXPECT_LE(m.reflectance.maxCoeff(), 1.0) << m.name;
    EXPECT_GE(m.emission.minCoeff(), 0.0) << m.name;
    EXPECT_NEAR(luminance(m.reflectance), rd.at(m.name), 1e-12) << m.name;
    const double e = ed.count(m.name) ? ed.at(m.name) : 0.0;
    EXPECT_NEAR(luminance(m.emission), e, 1e-12 * (1 + e)) << m.name;
    if (m.name == "grey") expect_rgb(m.reflectance, 0.6, 0.6, 0.6, 0.0, "flat cspec");
  }
  // Mapped: wall (0, 0.2), green (550 nm), dark (y = 0), glow's rd (y = 0),
  // yellow (0.5, 0.5), and glow's emission (0, 0); the cloth spectrum, illuminant A and
  // their mix with a little yellow are inside the gamut.
  EXPECT_TRUE(has_warning(s, "6 colour(s) outside the RGB gamut (5 reflectance, 1 emission)"))
      << (s.warnings.empty() ? "" : s.warnings.front());
}

}  // namespace
}  // namespace hrad

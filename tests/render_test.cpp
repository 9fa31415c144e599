#include "core/output/render.h"

#include "core/output/ply_writer.h"
#include "core/scene/render_mesh.h"
#include "core/scene/scene.h"
#include "tests/read_text.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

namespace hrad {
namespace {

constexpr double kPi = std::numbers::pi;

/// The square [-1,1]^2 in z = 0 as one quad, corners counter-clockwise from (-1,-1),
/// with the given radiosity at each corner.
RenderMesh square(const std::array<double, 4>& b) {
  RenderMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  for (double x : b) {
    m.radiosity.push_back(Rgb::Constant(x));
    m.reflectance.push_back(Rgb::Constant(0.5));
  }
  m.polys = {{0, 1, 2, 3}};
  return m;
}

/// Looks at the origin from +z; the image's half-height at z = 0 is 2, so the square
/// covers the central half of the picture (x and y from 1/4 to 3/4 of the size).
Camera head_on() {
  Camera c;
  c.eye = Vec3(0, 0, 5);
  c.target = Vec3::Zero();
  c.up = Vec3::UnitY();
  c.fov_y_deg = 2 * std::atan(2.0 / 5.0) * 180 / kPi;
  return c;
}

std::filesystem::path temp_path(const std::string& name) {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         (std::string("hrad_") + info->name() + "_" + std::to_string(::getpid()) + "_" + name);
}

using test::read_text;

TEST(Render, EmittingQuadHeadOnCoversItsRegionUniformly) {
  const RenderMesh m = square({3, 3, 3, 3});
  const Image img = render_radiance(m, head_on(), 64, 48);
  ASSERT_EQ(img.radiance.size(), 64u * 48u);
  // Horizontally the image spans +-2 * 64/48 at z = 0, so the square covers pixel
  // columns whose centres lie within +-1: x in [32 - 12, 32 + 12); rows [12, 36).
  int covered = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool inside = x >= 20 && x < 44 && y >= 12 && y < 36;
      const std::size_t p = static_cast<std::size_t>(y) * 64 + x;
      ASSERT_EQ(img.coverage[p], inside ? 1.0f : 0.0f) << x << "," << y;
      // Radiance of a Lambertian emitter: L = B / pi, the same everywhere on it.
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(img.radiance[p][c], inside ? 3 / kPi : 0.0, 1e-12) << x << "," << y;
      covered += inside;
    }
  }
  EXPECT_EQ(covered, 24 * 24);
}

TEST(Render, SupersamplingGivesFractionalCoverageAtEdges) {
  // 66 x 66 pixels: the square's edges fall at pixel coordinates 16.5 and 49.5, i.e.
  // exactly between the two 2x2 sub-samples of the edge pixels.
  const RenderMesh m = square({1, 1, 1, 1});
  const Image img = render_radiance(m, head_on(), 66, 66, 2);
  EXPECT_FLOAT_EQ(img.coverage[33 * 66 + 33], 1.0f);
  EXPECT_FLOAT_EQ(img.coverage[33 * 66 + 16], 0.5f);   // left edge
  EXPECT_FLOAT_EQ(img.coverage[33 * 66 + 49], 0.5f);   // right edge
  EXPECT_FLOAT_EQ(img.coverage[16 * 66 + 16], 0.25f);  // corner
  EXPECT_FLOAT_EQ(img.coverage[33 * 66 + 15], 0.0f);
  EXPECT_NEAR(img.at(16, 33)[0], 0.5 / kPi, 1e-12);
  EXPECT_THROW((void)render_radiance(m, head_on(), 8, 8, 0), std::invalid_argument);
}

TEST(Render, QuadVertexValuesInterpolateBilinearly) {
  // B = 1 at corner 0 only: B(x, y) = (1-u)(1-v) with u = (x+1)/2, v = (y+1)/2. This
  // fixes the corner order of Embree's quad parametrisation.
  const RenderMesh m = square({1, 0, 0, 0});
  const Camera cam = head_on();
  const int n = 40;  // square covers pixels [10, 30) in both directions
  const Image img = render_radiance(m, cam, n, n);
  double prev_row = -1;
  for (int y = 10; y < 30; ++y) {
    for (int x = 10; x < 30; ++x) {
      const double wx = 4.0 * (x + 0.5) / n - 2, wy = 2 - 4.0 * (y + 0.5) / n;  // world
      const double expected = (1 - (wx + 1) / 2) * (1 - (wy + 1) / 2) / kPi;
      ASSERT_NEAR(img.at(x, y)[1], expected, 1e-6) << x << "," << y;
    }
    // Rows go down the picture, towards y = -1 where corner 0 is: brighter each row.
    EXPECT_GT(img.at(15, y)[0], prev_row);
    prev_row = img.at(15, y)[0];
  }
}

TEST(Render, TriangleVertexValuesInterpolateLinearly) {
  RenderMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}};
  m.radiosity = {Rgb(0, 0, 1), Rgb(2, 0, 1), Rgb(0, 4, 1)};
  m.reflectance.assign(3, Rgb::Constant(0.5));
  m.polys = {{0, 1, 2, RenderMesh::kNoVertex}};
  const int n = 40;
  const Image img = render_radiance(m, head_on(), n, n);
  for (int y = 10; y < 30; ++y) {
    for (int x = 10; x < 30; ++x) {
      const double wx = 4.0 * (x + 0.5) / n - 2, wy = 2 - 4.0 * (y + 0.5) / n;
      const double u = (wx + 1) / 2, v = (wy + 1) / 2;
      if (u + v > 0.98) continue;  // outside, or too near the hypotenuse to be sure
      const Rgb expected = Rgb(2 * u, 4 * v, 1) / kPi;
      ASSERT_LT((img.at(x, y) - expected).abs().maxCoeff(), 1e-6) << x << "," << y;
    }
  }
}

TEST(Render, ToneMapFollowsTheDocumentedSteps) {
  ToneMap clamp;
  clamp.reinhard = false;
  EXPECT_EQ(tone_map(Rgb(1, 2, 0), 1.0, clamp), (std::array<std::uint8_t, 3>{255, 255, 0}));
  // Reinhard: 1 -> 0.5, then sRGB: 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 188.
  EXPECT_EQ(tone_map(Rgb(1, 1, 1), 1.0, ToneMap{}), (std::array<std::uint8_t, 3>{188, 188, 188}));
  // Automatic exposure: the log-average luminance goes to the key.
  const std::vector<Rgb> values = {Rgb::Constant(2), Rgb::Constant(8), Rgb::Zero()};
  EXPECT_NEAR(choose_exposure(values, ToneMap{}), 0.18 / 4.0, 1e-12);
  ToneMap fixed;
  fixed.exposure = 3;
  EXPECT_EQ(choose_exposure(values, fixed), 3.0);
  EXPECT_EQ(choose_exposure(std::vector<Rgb>{Rgb::Zero()}, ToneMap{}), 1.0);
}

TEST(Render, PngFileHasTheRenderedPixels) {
  const RenderMesh m = square({2, 2, 2, 2});
  const auto path = temp_path("quad.png");
  render_png(m, head_on(), 64, 48, path);
  const std::string bytes = read_text(path);
  std::filesystem::remove(path);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  int w = 0, h = 0, comp = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                            static_cast<int>(bytes.size()), &w, &h, &comp, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 64);
  EXPECT_EQ(h, 48);
  // Uniform surface: automatic exposure puts it at the key 0.18 -> Reinhard 0.1525
  // -> sRGB 0.4285 -> 109. Background black.
  const auto at = [&](int x, int y, int c) { return px[3 * (y * 64 + x) + c]; };
  EXPECT_EQ(at(32, 24, 0), 109);
  EXPECT_EQ(at(21, 13, 2), 109);
  EXPECT_EQ(at(2, 2, 1), 0);
  EXPECT_EQ(at(44, 24, 0), 0);
  stbi_image_free(px);
}

TEST(Render, RejectsBadMeshesAndCameras) {
  RenderMesh m = square({1, 1, 1, 1});
  Camera bad = head_on();
  bad.up = Vec3(0, 0, 1);  // parallel to the view direction
  EXPECT_THROW((void)render_radiance(m, bad, 8, 8), std::invalid_argument);
  m.polys[0][2] = 9;
  EXPECT_THROW((void)render_radiance(m, head_on(), 8, 8), std::invalid_argument);
  m = square({1, 1, 1, 1});
  m.radiosity.pop_back();
  EXPECT_THROW(check_render_mesh(m), std::invalid_argument);
  // solution.ply stores 32-bit floats: a radiosity beyond them would be written as inf.
  m = square({1, 1, 1, 1e39});
  EXPECT_THROW(check_render_mesh(m), std::invalid_argument);
  EXPECT_THROW((void)encode_ply(m, ToneMap{}), std::invalid_argument);
  m = square({1, 1, 1, 1e38});
  EXPECT_NO_THROW(check_render_mesh(m));
}

TEST(Render, MeshFromEmissionSplitsLargePolygonsAndCopiesEmission) {
  Scene sc;
  sc.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},   {0, 1, 0}, {2, 0, 0},
                 {3, 0, 0}, {3, 1, 0}, {2.5, 2, 0}, {2, 1, 0}};
  sc.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 0, 1, 3};
  Material lamp;
  lamp.emission = Rgb(1, 2, 3);
  sc.materials = {Material{}, lamp};
  sc.faces = {{0, 4, 1}, {4, 5, 0}, {9, 3, 0}};
  const RenderMesh m = render_mesh_from_emission(sc);
  EXPECT_EQ(m.positions.size(), 4u + 5u + 3u);  // per-face vertices
  ASSERT_EQ(m.polys.size(), 1u + 3u + 1u);      // pentagon -> 3 triangles
  EXPECT_FALSE(RenderMesh::is_triangle(m.polys[0]));
  for (std::size_t i = 1; i < 5; ++i) EXPECT_TRUE(RenderMesh::is_triangle(m.polys[i]));
  EXPECT_TRUE((m.radiosity[0] == Rgb(1, 2, 3)).all());
  EXPECT_TRUE((m.radiosity[4] == Rgb::Zero()).all());
  EXPECT_TRUE((m.reflectance[4] == Rgb::Constant(0.5)).all());
  EXPECT_NO_THROW(check_render_mesh(m));
}

// ---------------------------------------------------------------------------------
// PLY

/// A minimal reader for the PLY files write_ply produces.
struct PlyContent {
  std::vector<std::string> header;
  std::vector<std::array<float, 6>> vertices;  // x y z r g b radiosity
  std::vector<std::array<std::uint8_t, 3>> colours;
  std::vector<std::vector<std::int32_t>> faces;
  std::size_t trailing = 0;  // bytes left after the faces
};

template <typename T>
T get(const std::string& s, std::size_t& pos) {
  T v;
  if (pos + sizeof(T) > s.size()) throw std::runtime_error("PLY body too short");
  std::memcpy(&v, s.data() + pos, sizeof(T));  // test host is little-endian (x86)
  pos += sizeof(T);
  return v;
}

PlyContent parse_ply(const std::string& bytes) {
  PlyContent out;
  std::size_t pos = 0;
  std::size_t nv = 0, nf = 0;
  while (true) {
    const std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) throw std::runtime_error("no end_header");
    const std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    out.header.push_back(line);
    std::sscanf(line.c_str(), "element vertex %zu", &nv);
    std::sscanf(line.c_str(), "element face %zu", &nf);
    if (line == "end_header") break;
  }
  for (std::size_t i = 0; i < nv; ++i) {
    std::array<float, 6> v{};
    for (float& f : v) f = get<float>(bytes, pos);
    out.vertices.push_back(v);
    std::array<std::uint8_t, 3> c{};
    for (auto& b : c) b = get<std::uint8_t>(bytes, pos);
    out.colours.push_back(c);
  }
  for (std::size_t i = 0; i < nf; ++i) {
    const auto k = get<std::uint8_t>(bytes, pos);
    std::vector<std::int32_t> f;
    for (int j = 0; j < k; ++j) f.push_back(get<std::int32_t>(bytes, pos));
    out.faces.push_back(f);
  }
  out.trailing = bytes.size() - pos;
  return out;
}

TEST(Ply, WritesAReadableBinaryMeshWithQuadsAndTriangles) {
  RenderMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0.5}};
  m.radiosity = {Rgb(1, 2, 3), Rgb(0, 0, 0), Rgb(0.5, 0.5, 0.5), Rgb(10, 10, 10),
                 Rgb(0.25, 0, 1e-3)};
  m.reflectance.assign(5, Rgb::Constant(0.5));
  m.polys = {{0, 1, 2, 3}, {1, 4, 2, RenderMesh::kNoVertex}};
  const auto path = temp_path("mesh.ply");
  write_ply(m, path);
  const std::string bytes = read_text(path);
  std::filesystem::remove(path);

  const PlyContent ply = parse_ply(bytes);
  ASSERT_GE(ply.header.size(), 4u);
  EXPECT_EQ(ply.header[0], "ply");
  EXPECT_EQ(ply.header[1], "format binary_little_endian 1.0");
  const auto has = [&](const std::string& l) {
    return std::find(ply.header.begin(), ply.header.end(), l) != ply.header.end();
  };
  EXPECT_TRUE(has("element vertex 5"));
  EXPECT_TRUE(has("element face 2"));
  EXPECT_TRUE(has("property float radiosity_g"));
  EXPECT_TRUE(has("property uchar blue"));
  EXPECT_TRUE(has("property list uchar int vertex_indices"));
  // Size: header + 27 bytes per vertex + (1 + 4*4) + (1 + 3*4) for the faces.
  const std::size_t header_bytes = bytes.find("end_header\n") + 11;
  EXPECT_EQ(bytes.size(), header_bytes + 5 * 27 + 17 + 13);
  EXPECT_EQ(ply.trailing, 0u);

  ASSERT_EQ(ply.vertices.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(ply.vertices[i][c], static_cast<float>(m.positions[i][c]));
      EXPECT_EQ(ply.vertices[i][3 + c], static_cast<float>(m.radiosity[i][c]));
    }
  }
  // Colours follow the tone map: black stays black, brighter vertices are brighter.
  EXPECT_EQ(ply.colours[1], (std::array<std::uint8_t, 3>{0, 0, 0}));
  EXPECT_GT(ply.colours[3][0], ply.colours[2][0]);
  EXPECT_GT(ply.colours[0][2], ply.colours[0][0]);
  ASSERT_EQ(ply.faces.size(), 2u);
  EXPECT_EQ(ply.faces[0], (std::vector<std::int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(ply.faces[1], (std::vector<std::int32_t>{1, 4, 2}));
}

TEST(Ply, EmptyMeshIsAValidFile) {
  const PlyContent ply = parse_ply(encode_ply(RenderMesh{}));
  EXPECT_TRUE(ply.vertices.empty());
  EXPECT_TRUE(ply.faces.empty());
  EXPECT_EQ(ply.trailing, 0u);
}

}  // namespace
}  // namespace hrad

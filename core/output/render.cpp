#include "core/output/render.h"

#include "core/base/atomic_file.h"
#include "core/base/interrupt.h"
#include "core/raycast/ray_scene.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

// stb_image_write is header-only; its implementation lives here, with static linkage so
// another translation unit may include it too without clashing symbols.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace hrad {

// ---------------------------------------------------------------------------------
// RenderMesh

void check_render_mesh(const RenderMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (mesh.radiosity.size() != n || mesh.reflectance.size() != n)
    throw std::invalid_argument(
        fmt::format("RenderMesh: {} positions but {} radiosity and {} reflectance values", n,
                    mesh.radiosity.size(), mesh.reflectance.size()));
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.positions[i].allFinite() || !mesh.reflectance[i].allFinite() ||
        !mesh.radiosity[i].allFinite() || (mesh.radiosity[i] < 0).any())
      throw std::invalid_argument(
          fmt::format("RenderMesh: vertex {} has a non-finite or negative value", i));
    // solution.ply stores 32-bit floats: beyond their range a value would be inf.
    if ((mesh.radiosity[i] > static_cast<double>(std::numeric_limits<float>::max())).any())
      throw std::invalid_argument(
          fmt::format("RenderMesh: vertex {} has radiosity {:g}, beyond the range of 32-bit floats",
                      i, mesh.radiosity[i].maxCoeff()));
  }
  for (std::size_t p = 0; p < mesh.polys.size(); ++p) {
    const auto& q = mesh.polys[p];
    const int k = RenderMesh::is_triangle(q) ? 3 : 4;
    for (int c = 0; c < k; ++c)
      if (q[c] >= n)
        throw std::invalid_argument(fmt::format("RenderMesh: polygon {} indexes past the end", p));
  }
}

RenderMesh render_mesh_from_emission(const Scene& scene) {
  RenderMesh m;
  auto add_vertex = [&](const Vec3& p, const Material& mat) {
    m.positions.push_back(p);
    m.radiosity.push_back(mat.emission);
    m.reflectance.push_back(mat.reflectance);
    return static_cast<std::uint32_t>(m.positions.size() - 1);
  };
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    const Material& mat = scene.face_material(f);
    std::vector<std::uint32_t> ids;
    for (std::uint32_t k = 0; k < face.count; ++k)
      ids.push_back(add_vertex(scene.vertices[scene.indices[face.first + k]], mat));
    if (face.count == 3) {
      m.polys.push_back({ids[0], ids[1], ids[2], RenderMesh::kNoVertex});
    } else if (face.count == 4) {
      m.polys.push_back({ids[0], ids[1], ids[2], ids[3]});
    } else {
      for (std::size_t s = 1; s + 1 < ids.size(); ++s)
        m.polys.push_back({ids[0], ids[s], ids[s + 1], RenderMesh::kNoVertex});
    }
  }
  return m;
}

// ---------------------------------------------------------------------------------
// Tone mapping

double choose_exposure(std::span<const Rgb> radiance, const ToneMap& tm) {
  const double scale = std::exp2(tm.stops);
  if (tm.exposure > 0) return tm.exposure * scale;
  double log_sum = 0;
  std::size_t count = 0;
  for (const Rgb& c : radiance) {
    const double y = luminance(c);
    if (y > 0 && std::isfinite(y)) {
      log_sum += std::log(y);
      ++count;
    }
  }
  if (count == 0) return scale;
  return scale * tm.key / std::exp(log_sum / static_cast<double>(count));
}

namespace {

double srgb_encode(double x) {
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

}  // namespace

std::array<std::uint8_t, 3> tone_map(const Rgb& radiance, double exposure, const ToneMap& tm) {
  std::array<std::uint8_t, 3> out{};
  for (int c = 0; c < 3; ++c) {
    double x = std::max(0.0, exposure * radiance[c]);  // NaN -> 0
    x = std::isinf(x) ? 1.0 : tm.reinhard ? x / (1.0 + x) : std::min(x, 1.0);
    const double s = std::clamp(srgb_encode(x), 0.0, 1.0);
    out[c] = static_cast<std::uint8_t>(std::lround(255.0 * s));
  }
  return out;
}

double image_exposure(const Image& img, const ToneMap& tm) {
  std::vector<Rgb> covered;
  for (std::size_t i = 0; i < img.radiance.size(); ++i)
    if (img.coverage[i] > 0) covered.push_back(img.radiance[i]);
  return choose_exposure(covered, tm);
}

namespace {

std::vector<std::uint8_t> tone_map_pixels(const Image& img, const ToneMap& tm, double k) {
  std::vector<std::uint8_t> rgb(3 * img.radiance.size());
  for (std::size_t i = 0; i < img.radiance.size(); ++i) {
    const auto px = tone_map(img.radiance[i], k, tm);
    std::copy(px.begin(), px.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
  }
  return rgb;
}

}  // namespace

std::vector<std::uint8_t> tone_map_image(const Image& img, const ToneMap& tm) {
  return tone_map_pixels(img, tm, image_exposure(img, tm));
}

// ---------------------------------------------------------------------------------
// Rendering

Vec3 camera_ray(const Camera& cam, int width, int height, double px, double py) {
  const Vec3 fwd = cam.target - cam.eye;
  const Vec3 right = fwd.cross(cam.up);
  if (!(fwd.norm() > 0) || !(right.norm() > 1e-12 * fwd.norm() * cam.up.norm()) ||
      !(cam.fov_y_deg > 0 && cam.fov_y_deg < 180))
    throw std::invalid_argument("camera: degenerate view (eye, target, up or fov)");
  const Vec3 f = fwd.normalized();
  const Vec3 r = right.normalized();
  const Vec3 u = r.cross(f);
  const double half = std::tan(0.5 * cam.fov_y_deg * std::numbers::pi / 180.0);
  const double aspect = static_cast<double>(width) / height;
  const double sx = (2.0 * px / width - 1.0) * half * aspect;
  const double sy = (1.0 - 2.0 * py / height) * half;
  return f + sx * r + sy * u;
}

namespace {

/// Radiosity at surface coordinates (u, v) of polygon q, with Embree's conventions
/// (see RayHit): barycentric for triangles, bilinear from corner 0 for quads.
Rgb interpolate(const RenderMesh& mesh, const std::array<std::uint32_t, 4>& q, double u, double v) {
  const auto& b = mesh.radiosity;
  if (RenderMesh::is_triangle(q)) return (1 - u - v) * b[q[0]] + u * b[q[1]] + v * b[q[2]];
  return (1 - u) * (1 - v) * b[q[0]] + u * (1 - v) * b[q[1]] + u * v * b[q[2]] +
         (1 - u) * v * b[q[3]];
}

RayScene ray_scene_of(const RenderMesh& mesh) {
  std::vector<std::uint32_t> indices;
  std::vector<PolygonRange> ranges;
  indices.reserve(4 * mesh.polys.size());
  ranges.reserve(mesh.polys.size());
  for (const auto& q : mesh.polys) {
    const std::uint32_t k = RenderMesh::is_triangle(q) ? 3 : 4;
    ranges.push_back({static_cast<std::uint32_t>(indices.size()), k});
    indices.insert(indices.end(), q.begin(), q.begin() + k);
  }
  return RayScene(mesh.positions, indices, ranges);
}

}  // namespace

Image render_radiance(const RenderMesh& mesh, const Camera& cam, int width, int height,
                      int supersample) {
  if (width < 1 || height < 1 || supersample < 1 || supersample > 16)
    throw std::invalid_argument(
        fmt::format("render: bad size {}x{} or supersample {}", width, height, supersample));
  check_render_mesh(mesh);
  (void)camera_ray(cam, width, height, 0, 0);  // validates the camera before going parallel
  const RayScene rays = ray_scene_of(mesh);

  Image img;
  img.width = width;
  img.height = height;
  const auto pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  img.radiance.assign(pixels, Rgb::Zero());
  img.coverage.assign(pixels, 0.0f);
  const int s = supersample;
  const double inv_samples = 1.0 / (s * s);

  // Each iteration writes only its own row: no shared state but the (thread-safe)
  // RayScene.
#pragma omp parallel for schedule(dynamic, 1)
  for (int y = 0; y < height; ++y) {
    if (interrupted()) continue;  // then abandoned below
    for (int x = 0; x < width; ++x) {
      Rgb sum = Rgb::Zero();
      int hits = 0;
      for (int j = 0; j < s; ++j) {
        for (int i = 0; i < s; ++i) {
          const Vec3 dir = camera_ray(cam, width, height, x + (i + 0.5) / s, y + (j + 0.5) / s);
          auto hit = rays.intersect(cam.eye, dir);
          if (!hit) continue;
          if (rays.normal(hit->prim).dot(dir) > 0) {
            // A back: the front of a coincident element (the other side of a
            // two-sided sheet, core/scene/back_faces.h) wins, as it would for the solver.
            const double win = 4 * RayScene::kEndpointEpsilon * rays.scale() / dir.norm();
            const double start = std::max(hit->t - win, 0.0);
            const auto front =
                rays.intersect(cam.eye + start * dir, dir, hit->t - start + win, hit->prim);
            if (front && rays.normal(front->prim).dot(dir) < 0) hit = front;
          }
          ++hits;
          sum += interpolate(mesh, mesh.polys[hit->prim], hit->u, hit->v);
        }
      }
      const std::size_t p = static_cast<std::size_t>(y) * width + x;
      img.radiance[p] = sum * (inv_samples / std::numbers::pi);
      img.coverage[p] = static_cast<float>(hits * inv_samples);
    }
  }
  throw_if_interrupted();
  return img;
}

std::string encode_png(int width, int height, std::span<const std::uint8_t> rgb) {
  if (width < 1 || height < 1 ||
      rgb.size() != 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("encode_png: pixel buffer does not match the size");
  std::string bytes;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &bytes, width, height, 3, rgb.data(), 3 * width))
    throw std::runtime_error("encode_png: stb_image_write failed");
  return bytes;
}

double write_png(const Image& img, const std::filesystem::path& out, const ToneMap& tm) {
  const double k = image_exposure(img, tm);
  write_file_atomically(out, encode_png(img.width, img.height, tone_map_pixels(img, tm, k)));
  return k;
}

double render_png(const RenderMesh& mesh, const Camera& cam, int width, int height,
                  const std::filesystem::path& out, const ToneMap& tm, int supersample) {
  return write_png(render_radiance(mesh, cam, width, height, supersample), out, tm);
}

}  // namespace hrad

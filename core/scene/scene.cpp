#include "core/scene/scene.h"

#include "core/base/interrupt.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <utility>

namespace hrad {

std::vector<Vec3> Scene::face_vertices(std::size_t f) const {
  const Face& face = faces[f];
  std::vector<Vec3> p;
  p.reserve(face.count);
  for (std::uint32_t i = 0; i < face.count; ++i) p.push_back(vertices[indices[face.first + i]]);
  return p;
}

Vec3 Scene::face_normal(std::size_t f) const { return polygon_normal(face_vertices(f)); }

double Scene::face_area(std::size_t f) const { return polygon_area(face_vertices(f)); }

Aabb Scene::bounds() const {
  Aabb b;
  for (const Face& face : faces)
    for (std::uint32_t i = 0; i < face.count; ++i) b.extend(vertices[indices[face.first + i]]);
  return b;
}

Aabb Scene::bulk_bounds(double share) const {
  Aabb b;
  if (faces.empty()) return b;
  // Each face's area is shared out among its corners, so that one large face spans
  // its whole extent (its centroid alone would collapse a floor to a point).
  std::vector<std::pair<const Vec3*, double>> corner;  // (position, weight)
  double total = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const double a = face_area(f);
    total += a;
    for (std::uint32_t i = 0; i < faces[f].count; ++i)
      corner.emplace_back(&vertices[indices[faces[f].first + i]], a / faces[f].count);
  }
  if (!(total > 0)) return bounds();
  std::vector<std::pair<double, double>> at(corner.size());  // (coordinate, weight)
  for (int axis = 0; axis < 3; ++axis) {
    throw_if_interrupted();  // (a sort of 4 M corners cannot stop midway)
    for (std::size_t k = 0; k < corner.size(); ++k)
      at[k] = {(*corner[k].first)[axis], corner[k].second};
    std::sort(at.begin(), at.end());
    const double lo = 0.5 * (1 - share) * total, hi = 0.5 * (1 + share) * total;
    double sum = 0;
    b.lo[axis] = at.front().first;
    b.hi[axis] = at.back().first;
    bool low_set = false;
    for (const auto& [x, a] : at) {
      sum += a;
      if (!low_set && sum >= lo) {
        b.lo[axis] = x;
        low_set = true;
      }
      if (sum >= hi) {
        b.hi[axis] = x;
        break;
      }
    }
  }
  return b;
}

double Scene::total_area() const {
  double a = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) a += face_area(f);
  return a;
}

Rgb Scene::emitted_power() const {
  Rgb power = Rgb::Zero();
  for (std::size_t f = 0; f < faces.size(); ++f) power += face_material(f).emission * face_area(f);
  return power;
}

double Scene::max_channel_emitted_power() const {
  double power = 0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    power += face_area(f) * face_material(f).emission.maxCoeff();
  return power;
}

std::size_t Scene::emitter_count() const {
  return static_cast<std::size_t>(std::count_if(
      faces.begin(), faces.end(), [&](const Face& f) { return materials[f.material].emits(); }));
}

bool Scene::is_grey() const {
  auto grey = [](const Rgb& c) { return c[0] == c[1] && c[1] == c[2]; };
  return std::all_of(materials.begin(), materials.end(),
                     [&](const Material& m) { return grey(m.reflectance) && grey(m.emission); });
}

int Scene::up_axis() const {
  if (declared_up >= 0) return declared_up;
  // Face area by axis: |vector area| per component (area times |normal|), by
  // Newell's sum without copying the vertices.
  Vec3 area_by_axis = Vec3::Zero();
  for (const Face& face : faces) {
    Vec3 n = Vec3::Zero();
    for (std::uint32_t i = 0; i < face.count; ++i)
      n += vertices[indices[face.first + i]].cross(
          vertices[indices[face.first + (i + 1) % face.count]]);
    area_by_axis += 0.5 * n.cwiseAbs();
  }
  std::string ext = std::filesystem::path(source).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".mgf") return area_by_axis.y() > 1.5 * area_by_axis.z() ? 1 : 2;
  return area_by_axis.z() > 1.5 * area_by_axis.y() ? 2 : 1;
}

namespace {

/// The camera of default_camera(), and whether it looks in through an open side.
std::pair<Camera, bool> side_camera(const Scene& s) {
  // Up is the scene's up axis. The camera looks horizontally into the scene from the
  // side with the least wall facing it: from outside through an open side (the
  // Cornell box's missing front wall), else from just inside the least-walled side
  // of a closed room, so that walls do not hide everything.
  const Aabb b = s.bounds();
  const int up = s.up_axis();
  const Vec3 e = b.extent();
  const double diag = b.diagonal();
  int best_axis = -1;
  double best_sign = 1, best_block = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (axis == up) continue;
    for (double sign : {1.0, -1.0}) {
      // Area of faces near this side's boundary plane that face into the box.
      const double plane = sign > 0 ? b.hi[axis] : b.lo[axis];
      double block = 0;
      for (std::size_t f = 0; f < s.faces.size(); ++f) {
        const auto p = s.face_vertices(f);
        if (std::abs(polygon_centroid(p)[axis] - plane) > 0.02 * e[axis] + 1e-12 * diag) continue;
        if (s.face_normal(f)[axis] * sign < -0.5) block += s.face_area(f);
      }
      if (block < best_block - 1e-9 * diag * diag) {
        best_block = block;
        best_axis = axis;
        best_sign = sign;
      }
    }
  }
  Camera cam;
  cam.up = Vec3::Unit(up);
  cam.target = b.center();
  const int side = 3 - up - best_axis;  // the other horizontal axis
  const double side_area = e[side] * e[up];
  const double half = 0.5 * std::max(e[side], e[up]);
  cam.eye = b.center();
  const bool open = best_block < 0.05 * side_area;
  if (open) {
    cam.fov_y_deg = 40.0;
    const double dist = half / std::tan(0.5 * cam.fov_y_deg * std::numbers::pi / 180.0);
    cam.eye[best_axis] = (best_sign > 0 ? b.hi[best_axis] : b.lo[best_axis]) + best_sign * dist;
  } else {
    cam.fov_y_deg = 60.0;
    cam.eye[best_axis] =
        (best_sign > 0 ? b.hi[best_axis] : b.lo[best_axis]) - best_sign * 0.02 * e[best_axis];
  }
  return {cam, open};
}

}  // namespace

std::optional<Camera> Scene::open_side_camera() const {
  auto [cam, open] = side_camera(*this);
  return open ? std::optional<Camera>(cam) : std::nullopt;
}

Camera Scene::default_camera() const { return side_camera(*this).first; }

}  // namespace hrad

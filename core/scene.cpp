#include "core/scene.h"

#include <algorithm>
#include <numbers>

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

double Scene::total_area() const {
  double a = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) a += face_area(f);
  return a;
}

std::size_t Scene::emitter_count() const {
  return static_cast<std::size_t>(std::count_if(faces.begin(), faces.end(), [&](const Face& f) {
    return materials[f.material].emits();
  }));
}

bool Scene::is_grey() const {
  auto grey = [](const Rgb& c) { return c[0] == c[1] && c[1] == c[2]; };
  return std::all_of(materials.begin(), materials.end(),
                     [&](const Material& m) { return grey(m.reflectance) && grey(m.emission); });
}

Camera Scene::default_camera() const {
  // Look along the axis in which the box is thinnest... no: rooms are usually
  // viewed along a horizontal axis. We take the up axis to be the one along which
  // most face area is horizontal (floors and ceilings), and look along the longer
  // remaining axis from just inside the box's far wall, so closed rooms are seen
  // from inside, as a photographer would.
  const Aabb b = bounds();
  Vec3 area_by_axis = Vec3::Zero();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = face_normal(f);
    area_by_axis += face_area(f) * n.cwiseAbs();
  }
  int up = 1;
  area_by_axis.maxCoeff(&up);
  const Vec3 e = b.extent();
  int a = (up + 1) % 3, c = (up + 2) % 3;
  // View along the shorter horizontal axis, so the wider one fills the image.
  const int view = e[a] <= e[c] ? a : c;
  const int side = view == a ? c : a;
  Camera cam;
  cam.up = Vec3::Unit(up);
  cam.target = b.center();
  cam.eye = b.center();
  // Step back along +view until the wider extent fits a 40 degree field.
  cam.fov_y_deg = 40.0;
  const double half = 0.5 * std::max(e[side], e[up]);
  const double dist = half / std::tan(0.5 * cam.fov_y_deg * std::numbers::pi / 180.0);
  // Stay inside the box (slightly in front of the far wall) when it is a room,
  // since walls would otherwise hide everything.
  cam.eye[view] = std::min(b.center()[view] + dist, b.hi[view] - 1e-3 * b.diagonal());
  if (cam.eye[view] - b.center()[view] < 0.5 * dist) cam.fov_y_deg = 55.0;
  return cam;
}

}  // namespace hrad

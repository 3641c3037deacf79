#include "ratchet/observe/container_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace ratchet {

namespace {

Vec3 scaled(const ContainerDef& c, const Vec3& p, bool expands, double s_c) {
  return expands ? Vec3(c.scale_center + s_c * (p - c.scale_center)) : p;
}

void cone_mesh(const ContainerDef& c, double s_c, ContainerMesh& m) {
  const int n = c.segments;
  const double half = M_PI / n;
  const double tan_theta = std::tan(c.opening_angle_deg * M_PI / 180.0);
  const double r_bottom = c.bottom_radius / std::cos(half);
  const double r_top = (c.bottom_radius + c.height * tan_theta) / std::cos(half);
  // Bottom corners 0..N-1, then top corners N..2N-1; corner j at azimuth (2j - 1) pi / N.
  for (int ring = 0; ring < 2; ++ring)
    for (int j = 0; j < n; ++j) {
      const double psi = (2.0 * j - 1.0) * half;
      const double r = ring == 0 ? r_bottom : r_top;
      const Vec3 p(r * std::cos(psi), r * std::sin(psi), ring == 0 ? 0.0 : c.height);
      // The corners are the side walls' (scene/scene_sections.cpp, build_cone_walls): they
      // move with them, whether or not the floor's material does.
      m.points.push_back(scaled(c, p, c.walls[1].expands, s_c));
    }
  std::vector<int> floor(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) floor[static_cast<std::size_t>(j)] = j;  // counter-clockwise seen from +z
  m.polygons.push_back(floor);
  m.wall.push_back(0);
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    // bottom k, top k, top k+1, bottom k+1: the right-hand normal points to the axis.
    m.polygons.push_back({k, n + k, n + k1, k1});
    m.wall.push_back(k + 1);
  }
}

void planes_mesh(const SceneDef& scene, double s_c, ContainerMesh& m) {
  const ContainerDef& c = scene.container;
  for (std::size_t i = 0; i < c.walls.size(); ++i) {
    const WallDef& w = c.walls[i];
    const Vec3& n = w.normal;
    int axis = 0;  // the coordinate axis least aligned with n (first on ties)
    for (int a = 1; a < 3; ++a)
      if (std::abs(n[a]) < std::abs(n[axis])) axis = a;
    const Vec3 u = n.cross(Vec3::Unit(axis)).normalized();
    const Vec3 v = n.cross(u);  // u x v = n: the corners below run counter-clockwise about n
    const double h = plane_patch_half_side(scene, static_cast<int>(i));
    const int first = static_cast<int>(m.points.size());
    for (const auto& [a, b] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}})
      m.points.push_back(scaled(c, Vec3(w.point + h * (a * u + b * v)), w.expands, s_c));
    m.polygons.push_back({first, first + 1, first + 2, first + 3});
    m.wall.push_back(static_cast<int>(i));
  }
}

}  // namespace

double plane_patch_half_side(const SceneDef& scene, int wall) {
  const Vec3& p = scene.container.walls[static_cast<std::size_t>(wall)].point;
  double reach = 0.0;
  for (const BodyDef& b : scene.bodies) reach = std::max(reach, (b.position - p).norm() + b.bounding_radius);
  return 2.0 * reach;
}

ContainerMesh container_mesh(const SceneDef& scene, double s_c) {
  ContainerMesh m;
  switch (scene.container.type) {
    case ContainerDef::Type::Cone: cone_mesh(scene.container, s_c, m); break;
    case ContainerDef::Type::Planes: planes_mesh(scene, s_c, m); break;
    case ContainerDef::Type::None: break;
  }
  return m;
}

}  // namespace ratchet

#include "ratchet/observe/bed_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace ratchet {

double body_scale(const SceneDef& scene, const State& state, int i) {
  return scene.bodies[static_cast<std::size_t>(i)].fixed ? 1.0 : state.s_p;
}

// The arithmetic is that of the former World::bed_height and RunObservers::bed_points,
// so bed_height, V/V0 and the VTK files keep every bit.
void place_body(const SceneDef& scene, const State& state, int i, PlacedBody& out) {
  const std::size_t k = static_cast<std::size_t>(i);
  const BodyDef& b = scene.bodies[k];
  const double sc = body_scale(scene, state, i);
  const Vec3& x = state.x[k];
  out.points.clear();
  switch (b.kind) {
    case ShapeKind::Sphere: {
      const double r = b.radius * sc;
      const double d = 1.0 / std::sqrt(3.0);
      for (int a = 0; a < 3; ++a)
        for (double sign : {-1.0, 1.0}) out.points.push_back(x + sign * r * Vec3::Unit(a));
      for (double sx : {-d, d})
        for (double sy : {-d, d})
          for (double sz : {-d, d}) out.points.push_back(x + r * Vec3(sx, sy, sz));
      out.top = x.z() + r;
      out.sphere_radius = r;
      out.faces = nullptr;
      return;
    }
    case ShapeKind::Polyhedron: {
      const ConvexPolyhedron& shape = scene.shapes[static_cast<std::size_t>(b.shape)];
      const Mat3 R = state.q[k].toRotationMatrix();
      out.top = -HUGE_VAL;
      for (const Vec3& v : shape.vertices) {
        out.points.push_back(x + sc * (R * v));
        // Not points.back().z(): Eigen rounds (R v).z and R.row(2).dot(v) differently,
        // and bed_height has always been the latter.
        out.top = std::max(out.top, x.z() + sc * R.row(2).dot(v));
      }
      out.sphere_radius = 0.0;
      out.faces = &shape.faces;
      return;
    }
  }
}

std::vector<Vec3> bed_points(const SceneDef& scene, const State& state) {
  std::vector<Vec3> pts;
  PlacedBody body;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (scene.bodies[i].fixed) continue;
    place_body(scene, state, static_cast<int>(i), body);
    pts.insert(pts.end(), body.points.begin(), body.points.end());
  }
  return pts;
}

double bed_height(const SceneDef& scene, const State& state) {
  double top = 0.0;
  PlacedBody body;
  for (std::size_t i = 0; i < state.x.size(); ++i) {
    if (scene.bodies[i].fixed) continue;
    place_body(scene, state, static_cast<int>(i), body);
    top = std::max(top, body.top);  // NaN tops are skipped, as vertex by vertex
  }
  return top;
}

}  // namespace ratchet

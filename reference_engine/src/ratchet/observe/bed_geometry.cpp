#include "ratchet/observe/bed_geometry.hpp"

#include <algorithm>

namespace ratchet {

void place_body(const SceneDef& scene, const State& state, int i, PlacedBody& out) {
  const std::size_t k = static_cast<std::size_t>(i);
  const BodyDef& b = scene.bodies[k];
  shape_kind(b.kind).place(scene, b, state.x[k], state.q[k], body_scale(b, state.s_p), out);
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
  for (std::size_t i = 0; i < state.x.size(); ++i) {
    const BodyDef& b = scene.bodies[i];
    if (b.fixed) continue;
    const double t = shape_kind(b.kind).top(scene, b, state.x[i], state.q[i], body_scale(b, state.s_p));
    top = std::max(top, t);  // NaN tops are skipped, as vertex by vertex
  }
  return top;
}

}  // namespace ratchet

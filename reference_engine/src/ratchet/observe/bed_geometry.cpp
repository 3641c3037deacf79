#include "ratchet/observe/bed_geometry.hpp"

#include <algorithm>

namespace ratchet {

namespace {

constexpr int kParallelMinBodies = 256;  // fewer: a parallel region costs more than it saves

}  // namespace

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
  const int n = static_cast<int>(state.x.size());
  // A maximum is exact in any order, so any split among threads gives the same height;
  // it runs every step (the wall pressure), on the one thread otherwise.
#pragma omp parallel for schedule(static) reduction(max : top) if (n > kParallelMinBodies)
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const BodyDef& b = scene.bodies[k];
    if (b.fixed) continue;
    const double t = shape_kind(b.kind).top(scene, b, state.x[k], state.q[k], body_scale(b, state.s_p));
    top = std::max(top, t);  // NaN tops are skipped, as vertex by vertex
  }
  return top;
}

}  // namespace ratchet

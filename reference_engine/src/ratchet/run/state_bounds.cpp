#include "ratchet/run/state_bounds.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

namespace ratchet {

namespace {

constexpr int kNamed = 3;  // bodies named in the message; the count says how many more
constexpr int kParallelMinBodies = 256;  // fewer: a parallel region costs more than it saves

// The bounds of one state, body by body, for the look on all threads and the message.
// The container is an intersection of half-spaces (cone segments, floor, planes): a
// centre behind any of them by more than the body's own size is outside it.
struct Bounds {
  const World& world;
  std::vector<Vec3> wall_points;

  explicit Bounds(const World& w) : world(w) {
    for (int k = 0; k < static_cast<int>(w.scene().container.walls.size()); ++k) wall_points.push_back(w.wall_point(k));
  }
  double size(int i) const { return world.scene().bodies[static_cast<std::size_t>(i)].bounding_radius * world.body_scale(i); }
  // How far body i's centre lies behind wall w (positive: behind it).
  double behind(int i, int w) const {
    return -world.scene().container.walls[static_cast<std::size_t>(w)].normal.dot(
        world.state().x[static_cast<std::size_t>(i)] - wall_points[static_cast<std::size_t>(w)]);
  }
  // The wall body i's centre lies behind by more than its size, or -1.
  int outside(int i) const {
    const double reach = size(i) + world.scene().solver.contact_margin;
    for (int w = 0; w < static_cast<int>(wall_points.size()); ++w)
      if (behind(i, w) > reach) return w;
    return -1;
  }
  double travel(int i) const { return world.state().v[static_cast<std::size_t>(i)].norm() * world.scene().dt; }
};

// Whether any body breaks a bound, without saying which: it runs every step and almost
// always finds nothing, so it looks on all threads ("any" and the smallest size are exact
// in any order) and the message is made on one.
bool any_unphysical(const Bounds& bounds) {
  const std::vector<BodyDef>& bodies = bounds.world.scene().bodies;
  const int n = static_cast<int>(bodies.size());
  double r_min = std::numeric_limits<double>::infinity();
  bool bad = false;
#pragma omp parallel for schedule(static) reduction(min : r_min) reduction(|| : bad) if (n > kParallelMinBodies)
  for (int i = 0; i < n; ++i) {
    if (bodies[static_cast<std::size_t>(i)].fixed) continue;
    const double size = bounds.size(i);
    r_min = std::min(r_min, size);
    if (bounds.outside(i) >= 0 || bounds.travel(i) > size) bad = true;
  }
  return bad || bounds.world.stats().max_overlap > r_min;
}

}  // namespace

std::string unphysical_state(const World& world) {
  const Bounds bounds(world);
  if (!any_unphysical(bounds)) return "";
  const SceneDef& scene = world.scene();
  const int n = static_cast<int>(scene.bodies.size());
  std::string names;
  int outside = 0;
  double r_min = std::numeric_limits<double>::infinity();  // smallest free body, for the overlap bound
  for (int i = 0; i < n; ++i) {
    if (scene.bodies[static_cast<std::size_t>(i)].fixed) continue;
    r_min = std::min(r_min, bounds.size(i));
    const int w = bounds.outside(i);
    if (w >= 0 && ++outside <= kNamed) {
      char text[160];
      std::snprintf(text, sizeof text, "%sbody %d (centre %.3g behind wall %d, size %.3g)", names.empty() ? "" : ", ",
                    i, bounds.behind(i, w), w, bounds.size(i));
      names += text;
    }
  }
  if (outside > 0)
    return std::to_string(outside) + " bod" + (outside == 1 ? "y" : "ies") + " outside the container: " + names +
           (outside > kNamed ? ", ..." : "");
  // An overlap deeper than the smallest body's bounding radius: one body inside another
  // or inside a wall, which no contact law recovers from.
  const double deepest = world.stats().max_overlap;
  if (deepest > r_min) {
    for (const SolverContact& c : world.contacts()) {
      if (-c.geometry.gap < deepest) continue;
      char text[200];
      std::snprintf(text, sizeof text, "an overlap of %.3g between body %d and %s %d, deeper than the smallest body's "
                    "bounding radius %.3g", deepest, c.a, is_wall(c.b) ? "wall" : "body",
                    is_wall(c.b) ? wall_index(c.b) : c.b, r_min);
      return text;
    }
  }
  // A body that moved more than its own size in one step can pass through another body
  // or a wall between two detections: the step no longer resolves the motion. Energy
  // that grows without bound (a diverging solve) reaches this long before a NaN.
  const double h = scene.dt;
  for (int i = 0; i < n; ++i) {
    if (scene.bodies[static_cast<std::size_t>(i)].fixed) continue;
    const double travel = bounds.travel(i);
    const double size = bounds.size(i);
    if (travel > size) {
      char text[320];
      std::snprintf(text, sizeof text, "body %d moved %.3g in one step (speed %.3g, time.dt %.3g), more than its "
                    "bounding radius %.3g: the step cannot resolve its motion (a diverging solve, or time.dt too "
                    "large for the speeds of the scene)", i, travel, travel / h, h, size);
      return text;
    }
  }
  return "";
}

}  // namespace ratchet

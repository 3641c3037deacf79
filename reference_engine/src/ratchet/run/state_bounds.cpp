#include "ratchet/run/state_bounds.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

namespace ratchet {

namespace {

constexpr int kNamed = 3;  // bodies named in the message; the count says how many more
constexpr int kParallelMinBodies = 256;  // fewer: a parallel region costs more than it saves

// Whether any body breaks a bound of unphysical_state, without saying which: it runs
// every step and almost always finds nothing, so it looks on all threads ("any" and the
// smallest radius are exact in any order) and the message is made on one.
bool any_unphysical(const World& world) {
  const SceneDef& scene = world.scene();
  const State& s = world.state();
  const int n = static_cast<int>(scene.bodies.size());
  const int nw = static_cast<int>(scene.container.walls.size());
  const double margin = scene.solver.contact_margin;
  const double h = scene.dt;
  std::vector<Vec3> wall_points(static_cast<std::size_t>(nw));
  for (int w = 0; w < nw; ++w) wall_points[static_cast<std::size_t>(w)] = world.wall_point(w);
  double r_min = std::numeric_limits<double>::infinity();
  bool bad = false;
#pragma omp parallel for schedule(static) reduction(min : r_min) reduction(|| : bad) if (n > kParallelMinBodies)
  for (int i = 0; i < n; ++i) {
    const BodyDef& b = scene.bodies[static_cast<std::size_t>(i)];
    if (b.fixed) continue;
    const double size = b.bounding_radius * world.body_scale(i);
    r_min = std::min(r_min, size);
    const Vec3& x = s.x[static_cast<std::size_t>(i)];
    for (int w = 0; w < nw; ++w)
      if (scene.container.walls[static_cast<std::size_t>(w)].normal.dot(x - wall_points[static_cast<std::size_t>(w)]) <
          -(size + margin))
        bad = true;
    if (s.v[static_cast<std::size_t>(i)].norm() * h > size) bad = true;
  }
  return bad || world.stats().max_overlap > r_min;
}

}  // namespace

std::string unphysical_state(const World& world) {
  if (!any_unphysical(world)) return "";
  const SceneDef& scene = world.scene();
  const State& s = world.state();
  const int n = static_cast<int>(scene.bodies.size());
  const int nw = static_cast<int>(scene.container.walls.size());
  const double margin = scene.solver.contact_margin;
  // The container is an intersection of half-spaces (cone segments, floor, planes): a
  // centre behind any of them by more than the body's own size is outside it.
  std::string names;
  int outside = 0;
  double r_min = std::numeric_limits<double>::infinity();  // smallest free body, for the overlap bound
  for (int i = 0; i < n; ++i) {
    const BodyDef& b = scene.bodies[static_cast<std::size_t>(i)];
    if (b.fixed) continue;
    r_min = std::min(r_min, b.bounding_radius * world.body_scale(i));
    const double reach = b.bounding_radius * world.body_scale(i) + margin;
    for (int w = 0; w < nw; ++w) {
      const WallDef& wall = scene.container.walls[static_cast<std::size_t>(w)];
      const double d = wall.normal.dot(s.x[static_cast<std::size_t>(i)] - world.wall_point(w));
      if (d < -reach) {
        if (++outside <= kNamed) {
          char text[160];
          std::snprintf(text, sizeof text, "%sbody %d (centre %.3g behind wall %d, size %.3g)", names.empty() ? "" : ", ",
                        i, -d, w, reach - margin);
          names += text;
        }
        break;
      }
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
    const BodyDef& b = scene.bodies[static_cast<std::size_t>(i)];
    if (b.fixed) continue;
    const double travel = s.v[static_cast<std::size_t>(i)].norm() * h;
    const double size = b.bounding_radius * world.body_scale(i);
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

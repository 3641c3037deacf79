// Where the bed is: the placed shapes of its bodies, the bed height and the points
// whose convex hull is the bed (docs/method.md s. 10; docs/output-format.md,
// `bed_height` and "Bed volume"). Pure functions of the scene and a state.
#pragma once

#include <vector>

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

// Thermal scale of body i: s_p, or 1 for a fixed body (as the step scales it).
double body_scale(const SceneDef& scene, const State& state, int i);

// Body i as the state places it, at its thermal scale.
struct PlacedBody {
  // Points whose convex hull is the body: a polyhedron's world vertices; for a sphere
  // its 6 axis points and 8 diagonal surface points (an inscribed approximation).
  std::vector<Vec3> points;
  double top = 0.0;            // highest z: the sphere's top, the highest vertex
  double sphere_radius = 0.0;  // > 0: a sphere of this radius, centred at state.x[i]
  const std::vector<std::vector<int>>* faces = nullptr;  // a polyhedron's faces (indices into points)
};

// Fills `out` (its storage is reused). The one place observables look at shape kinds:
// a new kind is added here and every observable follows.
void place_body(const SceneDef& scene, const State& state, int i, PlacedBody& out);

// The points of place_body of every non-fixed body, in body order.
std::vector<Vec3> bed_points(const SceneDef& scene, const State& state);

// Highest point of any non-fixed body above z = 0 (never below 0): the largest
// PlacedBody::top, z + s_p r for a sphere and the highest vertex of a polyhedron.
double bed_height(const SceneDef& scene, const State& state);

}  // namespace ratchet

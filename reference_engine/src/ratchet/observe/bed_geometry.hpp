// Where the bed is: the placed shapes of its bodies, the bed height and the points
// whose convex hull is the bed (docs/method.md s. 10; docs/output-format.md,
// `bed_height` and "Bed volume"). Pure functions of the scene and a state.
#pragma once

#include <vector>

#include "ratchet/scene/shape_kinds.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

// Body i as the state places it, at its thermal scale, by its shape kind
// (scene/shape_kinds.hpp): every observable follows a new kind without a change here.
// Fills `out` (its storage is reused).
void place_body(const SceneDef& scene, const State& state, int i, PlacedBody& out);

// The points of place_body of every non-fixed body, in body order.
std::vector<Vec3> bed_points(const SceneDef& scene, const State& state);

// Highest point of any non-fixed body above z = 0 (never below 0): the largest
// PlacedBody::top, z + s_p r for a sphere and the highest vertex of a polyhedron.
double bed_height(const SceneDef& scene, const State& state);

}  // namespace ratchet

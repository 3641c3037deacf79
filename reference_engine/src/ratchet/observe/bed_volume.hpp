// Bed volume V(t): the volume of the convex hull of all particle vertices (paper s.3,
// "V is calculated from the convex hull of the vertices of all particles";
// docs/output-format.md, "Bed volume"). Pure functions of a point cloud or a state.
#pragma once

#include <vector>

#include "ratchet/core/types.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

// Volume of the convex hull of `points`, computed with Qhull (reentrant API, option
// 'FA': total facet area and volume). Qhull prints nothing.
// Throws std::invalid_argument for fewer than 4 points, non-finite points, or a
// degenerate cloud (coincident, collinear or coplanar points, relative to its size);
// std::runtime_error if Qhull fails for another reason.
double convex_hull_volume(const std::vector<Vec3>& points);

// The bed's volume: convex_hull_volume of bed_points (observe/bed_geometry.hpp).
double bed_volume(const SceneDef& scene, const State& state);

}  // namespace ratchet

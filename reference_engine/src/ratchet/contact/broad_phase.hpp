// Broad phase: a uniform grid of cubic cells sized by the largest bounding sphere, so
// each body is tested against the bodies of its 27 neighbouring cells only: O(N) work
// for a bed of similar particles (Ericson 2005, Real-Time Collision Detection, s. 7.1).
#pragma once

#include <utility>
#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

using BodyPair = std::pair<int, int>;

// Pairs (i < j) whose bounding spheres come closer than `margin`, sorted by (i, j) so
// that the list does not depend on the thread count.
void find_candidate_pairs(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin,
                          std::vector<BodyPair>& pairs);

}  // namespace ratchet

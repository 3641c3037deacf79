// Broad phase: a uniform grid of cubic cells sized by the largest bounding sphere, so
// each body is tested against the bodies of its 27 neighbouring cells only: O(N) work
// for a bed of similar particles (Ericson 2005, Real-Time Collision Detection, s. 7.1).
#pragma once

#include <utility>
#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

using BodyPair = std::pair<int, int>;

// The pair test of the broad phase: bounding spheres closer than `margin`. One
// expression for the grid search and for the kept list (contact/pair_list.hpp), so that
// both decide every pair alike, to the last bit.
inline bool within_reach(const Vec3& ci, const Vec3& cj, double ri, double rj, double margin) {
  const double reach = ri + rj + margin;
  return (ci - cj).squaredNorm() <= reach * reach;
}

// Pairs (i < j) whose bounding spheres come closer than `margin`, sorted by (i, j) so
// that the list does not depend on the thread count.
void find_candidate_pairs(const std::vector<Vec3>& centers, const std::vector<double>& radii, double margin,
                          std::vector<BodyPair>& pairs);

}  // namespace ratchet

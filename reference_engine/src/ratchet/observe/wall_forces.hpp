// Normal forces on the cone's side segments from the contacts of a step
// (docs/output-format.md: `wall_force_seg_<k>`, wall_profile.csv): lambda_n / h per
// contact. Pure functions of the scene and the solved contacts.
#pragma once

#include <vector>

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/scratch.hpp"

namespace ratchet {

// Indices (into scene.container.walls) of the side walls, in wall order: segment k is
// the k-th of them.
std::vector<int> side_wall_indices(const SceneDef& scene);

// Total normal force on each side segment (one entry per side wall, in contact order).
std::vector<double> side_segment_forces(const SceneDef& scene, const std::vector<SolverContact>& contacts);

// The side-wall contacts: their heights (contact point z) and normal forces, in
// contact order; `z` and `force` are cleared first.
void side_wall_contacts(const SceneDef& scene, const std::vector<SolverContact>& contacts, std::vector<double>& z,
                        std::vector<double>& force);

}  // namespace ratchet

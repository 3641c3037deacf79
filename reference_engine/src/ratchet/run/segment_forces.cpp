#include "ratchet/run/segment_forces.hpp"

#include "ratchet/observe/wall_forces.hpp"

namespace ratchet {

void SegmentForces::timeseries_columns(std::vector<std::string>& names) const {
  if (!scene_.outputs.segment_forces) return;
  const std::size_t sides = side_wall_indices(scene_).size();
  for (std::size_t k = 0; k < sides; ++k) names.push_back("wall_force_seg_" + std::to_string(k));
}

void SegmentForces::timeseries_values(const World& world, std::vector<double>& values) const {
  if (!scene_.outputs.segment_forces) return;
  const std::vector<double> f = side_segment_forces(scene_, world.contacts());
  values.insert(values.end(), f.begin(), f.end());
}

}  // namespace ratchet

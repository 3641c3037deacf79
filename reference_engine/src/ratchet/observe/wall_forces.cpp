#include "ratchet/observe/wall_forces.hpp"

#include "ratchet/core/contact_side.hpp"

namespace ratchet {

std::vector<int> side_wall_indices(const SceneDef& scene) {
  std::vector<int> out;
  for (std::size_t w = 0; w < scene.container.walls.size(); ++w)
    if (scene.container.walls[w].role == WallRole::Side) out.push_back(static_cast<int>(w));
  return out;
}

std::vector<double> side_segment_forces(const SceneDef& scene, const std::vector<SolverContact>& contacts) {
  const std::vector<int> sides = side_wall_indices(scene);
  std::vector<double> f(sides.size(), 0.0);
  for (const SolverContact& c : contacts) {
    if (!is_wall(c.b)) continue;
    const int w = wall_index(c.b);
    for (std::size_t k = 0; k < sides.size(); ++k)
      if (sides[k] == w) f[k] += c.lambda[0] / scene.dt;
  }
  return f;
}

void side_wall_contacts(const SceneDef& scene, const std::vector<SolverContact>& contacts, std::vector<double>& z,
                        std::vector<double>& force) {
  z.clear();
  force.clear();
  for (const SolverContact& c : contacts) {
    if (!is_wall(c.b) || scene.container.walls[static_cast<std::size_t>(wall_index(c.b))].role != WallRole::Side)
      continue;
    z.push_back(c.geometry.point.z());
    force.push_back(c.lambda[0] / scene.dt);
  }
}

}  // namespace ratchet

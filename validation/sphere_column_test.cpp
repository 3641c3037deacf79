// Validation 4: a column of 5 spheres on the floor. Each contact carries the weight of
// the spheres above it, and the column stands still for 10^4 steps.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"
#include "support/check_record.hpp"

namespace ratchet {
namespace {

TEST(SphereColumn, EachContactCarriesTheWeightAboveAndTheColumnStandsStill) {
  const SceneDef scene = load_scene(std::string(RATCHET_VALIDATION_DIR) + "/sphere_column/column.json");
  World world(scene);
  const int n = static_cast<int>(scene.bodies.size());
  double max_displacement = 0.0;
  run_world(world, {}, [&](const World& w) {
    for (int i = 0; i < n; ++i)
      max_displacement = std::max(max_displacement, (w.state().x[i] - scene.bodies[i].position).norm());
  });
  ASSERT_EQ(world.state().step, 10000);
  const double m = scene.bodies[0].mass, h = scene.dt;
  // Contact force below sphere k (0 at the bottom; the floor is below sphere 0).
  std::vector<double> force(static_cast<std::size_t>(n), -1.0);
  for (const SolverContact& c : world.contacts()) {
    const int upper = c.b < 0 ? c.a : std::max(c.a, c.b);
    if (c.b < 0 || std::abs(c.a - c.b) == 1) force[static_cast<std::size_t>(c.b < 0 ? 0 : upper)] = c.lambda[0] / h;
  }
  for (int k = 0; k < n; ++k) {
    const double weight_above = (n - k) * m * 1.0;
    EXPECT_TRUE(validation::check_rel("sphere column", "force below sphere " + std::to_string(k) + " / weight above",
                                      force[static_cast<std::size_t>(k)] / weight_above, 1.0, 1e-6,
                                      "brief: 1e-6; solver tolerance 1e-12"));
  }
  EXPECT_TRUE(validation::check_le("sphere column", "max displacement over 10^4 steps", max_displacement, 1e-9,
                                   "gaps closed exactly at rest; round-off only"));
}

}  // namespace
}  // namespace ratchet

// Validation 2: free fall onto the floor and rest. Before contact the Moreau-Jean
// scheme is the recurrence v_{k+1} = v_k - h g, z_{k+1} = z_k + h ((1 - theta) v_k +
// theta v_{k+1}); the engine must reproduce it exactly (same operations, same order).
// At rest the floor force equals the weight.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"
#include "support/check_record.hpp"

namespace ratchet {
namespace {

class FreeFall : public ::testing::TestWithParam<double> {};

TEST_P(FreeFall, MatchesDiscreteFreeFallThenCarriesTheWeight) {
  const double theta = GetParam();
  const std::string case_name = "free fall, theta = " + validation::format_number(theta);
  const SceneDef scene = load_scene(std::string(RATCHET_VALIDATION_DIR) + "/free_fall/sphere.json",
                                    {"solver.theta=" + validation::format_number(theta)});
  World world(scene);
  const double h = scene.dt, g = 1.0, r = scene.bodies[0].radius, m = scene.bodies[0].mass;
  double z = scene.bodies[0].position.z(), v = 0.0;
  double max_flight_diff = 0.0;
  bool in_flight = true;
  int flight_steps = 0;
  double force_at_rest = 0.0, max_rest_speed = 0.0;
  run_world(world, {}, [&](const World& w) {
    if (in_flight && w.stats().contacts == 0) {
      // The recurrence, written exactly as the engine evaluates it (theta = 1: x += h v).
      const double v_next = v + h * (-g);
      z += theta == 1.0 ? h * v_next : h * ((1.0 - theta) * v + theta * v_next);
      v = v_next;
      max_flight_diff = std::max(max_flight_diff, std::abs(w.state().x[0].z() - z));
      ++flight_steps;
    } else {
      in_flight = false;
    }
    if (w.state().t > 3.0) {  // long after landing (t ~ 1.73)
      force_at_rest = w.stats().wall_force_total;
      max_rest_speed = std::max(max_rest_speed, w.state().v[0].norm());
    }
  });
  EXPECT_GT(flight_steps, 1500);  // fall time sqrt(2 * 1.5) ~ 1.73 time units
  EXPECT_TRUE(validation::check_near(case_name, "max |z - z_discrete| in flight", max_flight_diff, 0.0, 0.0,
                                     "same recurrence, same floating-point operations: exact"));
  EXPECT_TRUE(validation::check_rel(case_name, "floor force at rest / weight", force_at_rest / (m * g), 1.0, 1e-9,
                                    "one contact, solved exactly: round-off only"));
  EXPECT_TRUE(validation::check_near(case_name, "height at rest - r", world.state().x[0].z() - r, 0.0, 1e-9,
                                     "inelastic landing closes the gap exactly; round-off only"));
  EXPECT_TRUE(validation::check_le(case_name, "max speed at rest", max_rest_speed, 1e-12, "round-off only"));
}

INSTANTIATE_TEST_SUITE_P(Theta, FreeFall, ::testing::Values(1.0, 0.5));

}  // namespace
}  // namespace ratchet

// The compliant law's tangential part (solver.tangential_law, docs/method.md s. 5): a box
// resting on the floor under gravity tilted by atan(0.3), inside the friction cone
// (mu = 0.5), so the rigid law holds it still. With the creep law its sticking contacts
// slide at c lambda_t for as long as they are loaded; with the spring law they move by
// c h per change of impulse, so once loaded the box stays where it is.
#include "ratchet/world/world.hpp"

#include <gtest/gtest.h>

#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

// The box's x after `steps` steps and after twice as many, with the given law.
std::pair<double, double> slide(const char* law, double compliance, int steps) {
  json j = json::parse(R"({
    "name": "tilted", "seed": 1, "gravity": [0.3, 0, -1], "time": {"dt": 0.004, "duration": 1.0},
    "solver": {"tolerance": 1e-10, "max_iterations": 2000},
    "container": {"type": "cone", "bottom_radius": 4.0, "opening_angle_deg": 0.0},
    "particles": {"bodies": [{"shape": "box", "half_extents": [0.5, 0.5, 0.25], "position": [0, 0, 0.25]}]}
  })");
  j["solver"]["compliance"] = compliance;
  j["solver"]["tangential_law"] = law;
  j["time"]["duration"] = 2 * steps * 0.004;
  World world(build_scene(j, "tilted.json"));
  double half = 0.0;
  run_world(world, {}, [&](const World& w) {
    if (w.state().step == steps) half = w.state().x[0].x();
  });
  return {half, world.state().x[0].x()};
}

TEST(TangentialLaw, TheCreepLawSlidesALoadedStickingContactAndTheSpringLawHoldsIt) {
  const int steps = 500;
  const auto [creep_half, creep_end] = slide("creep", 0.5, steps);
  const auto [spring_half, spring_end] = slide("spring", 0.5, steps);
  const auto [rigid_half, rigid_end] = slide("creep", 0.0, steps);
  // Creep: a steady slide, about c lambda_t per step (W_nn of a corner point about 3 / m,
  // lambda_t about m 0.3 h / 4): 0.5 * 3 * 0.3 * 0.004 / 4 = 4.5e-4 per unit time, 9e-4
  // over the second half; a quarter of it is a wide margin for the lever arms.
  EXPECT_GT(creep_end - creep_half, 2e-4);
  // Spring: it moved while its load was built up (c h per change of impulse), a small
  // part of what the creep law slides in the first half, and then no more (round-off of
  // positions of order 1: 1e-9 is far below the creep).
  EXPECT_LT(std::abs(spring_end - spring_half), 1e-9);
  EXPECT_LT(std::abs(spring_end), 0.1 * creep_half) << "spring " << spring_end << ", creep " << creep_half;
  // The rigid law ignores the tangential law: nothing to creep with.
  EXPECT_LT(std::abs(rigid_end - rigid_half), 1e-9);
}

TEST(TangentialLaw, ChangesNothingWithoutCompliance) {
  const auto creep = slide("creep", 0.0, 100);
  const auto spring = slide("spring", 0.0, 100);
  EXPECT_EQ(creep, spring);
}

}  // namespace
}  // namespace ratchet

// The container's expansion in the contact kinematics (docs/method.md s. 2): a point x of
// an expanding wall moves with eps_c (x - c0), so a grain sticking to the cone's floor is
// carried outward with it; container.floor_expands = false keeps the floor's material at
// rest while the side walls still expand.
#include "ratchet/world/world.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "ratchet/run/runner.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

// One sphere resting on the floor of a cylinder at r = 3, far from the side walls, heated
// from T = 0 to 100 with alpha_c = 1e-3 (the run stops at the end of the heating): the
// container scale grows by 10 %.
double radius_after_heating(bool floor_expands) {
  json j = json::parse(R"({
    "name": "floor", "time": {"dt": 0.004, "duration": 2.0},
    "solver": {"tolerance": 1e-10, "max_iterations": 200},
    "materials": {"friction": 0.5, "wall_friction": 0.5},
    "container": {"type": "cone", "bottom_radius": 8.5},
    "effects": {"particle_expansion": false},
    "thermal": {"T0": 0, "T1": 100, "heat_time": 2.0, "hold_time": 1.0, "cool_time": 2.0,
                "cycles": 1, "alpha_c": 1e-3},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [3.0, 0.0, 0.5]}]}
  })");
  j["container"]["floor_expands"] = floor_expands;
  World world(build_scene(j, "floor.json"));
  run_world(world, {});
  EXPECT_NEAR(world.state().s_c, 1.1, 1e-9);  // the side walls did expand in both cases
  return world.state().x[0].head<2>().norm();
}

TEST(ContainerExpansion, TheFloorCarriesAStickingGrainOutwardWithTheContainer) {
  // Rolling without slip, a solid sphere's centre moves at 2/7 of the floor's speed under
  // it (I = 2/5 m r^2); the floor's material at radius r moves at r (ds_c/dt) / s_c, so
  // the centre travels about 2/7 r ln(1.1). 5 %: r itself grows by the 2.7 % the sphere
  // travels, and the first step's impulse ends its slip.
  const double carried = radius_after_heating(true) - 3.0;
  EXPECT_NEAR(carried, 2.0 / 7.0 * 3.0 * std::log(1.1), 0.05 * 2.0 / 7.0 * 3.0 * std::log(1.1));
  // A floor at rest under the expanding side walls carries nothing: no force acts along
  // it (the centre ends at x = 3 to the last bit today); 1e-9 leaves room for a residual
  // of the 1e-10 solve, far below the expanding floor's carry of 0.08.
  EXPECT_NEAR(radius_after_heating(false), 3.0, 1e-9);
}

}  // namespace
}  // namespace ratchet

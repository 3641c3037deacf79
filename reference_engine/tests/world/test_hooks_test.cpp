// The planted-regression seam: drop_wall_expansion removes exactly the wall's expansion
// velocity from a contact with an expanding wall, and nothing else.
#include "ratchet/world/test_hooks.hpp"

#include <gtest/gtest.h>

#include "ratchet/world/world.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

// One sphere on the floor of a heated cone, off the axis: the floor point under it
// moves outwards with eps_c (p - c0).
SceneDef heated_sphere() {
  const json j = json::parse(R"({
    "name": "hook", "time": {"dt": 0.01, "duration": 0.05},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [1.0, 0.0, 0.49]}]},
    "thermal": {"T0": 0, "T1": 100, "heat_time": 1.0, "hold_time": 0.0, "cool_time": 1.0, "cycles": 1,
                "alpha_p": 1e-4, "alpha_c": 1e-3}
  })");
  return build_scene(j, "hook.json");
}

SolverContact floor_contact(bool drop) {
  test_hooks().drop_wall_expansion = drop;
  World w(heated_sphere());
  w.step();
  test_hooks().drop_wall_expansion = false;
  for (const SolverContact& c : w.contacts())
    if (is_wall(c.b)) return c;
  ADD_FAILURE() << "no wall contact";
  return SolverContact{};
}

TEST(TestHooks, DropWallExpansionRemovesOnlyTheWallsTerm) {
  const SolverContact on = floor_contact(false), off = floor_contact(true);
  const Vec3 with = on.u_expansion, without = off.u_expansion;
  // Without the hook the floor point at x = 1 recedes outwards: -eps_c (p - c0) has a
  // negative x part; the particle's own eps_p r is vertical (r from its centre).
  EXPECT_LT(with.x(), -1e-2);
  EXPECT_EQ(without.x(), 0.0);
  // What the hook removed is the wall's term, parallel to p - c0 (c0 the bottom centre);
  // 1e-12 relative: the difference of two sums of products of size ~0.1 (round-off only).
  const Vec3 removed = with - without, arm = on.geometry.point;
  EXPECT_LT(removed.cross(arm).norm(), 1e-12 * removed.norm() * arm.norm());
  EXPECT_EQ(off.geometry.point, on.geometry.point);  // same contact, same step
  EXPECT_FALSE(test_hooks().drop_wall_expansion);  // the program never sets it
}

}  // namespace
}  // namespace ratchet

// Kinetic energy: translation of non-fixed bodies, rotation in the body frame at the
// particle scale, and nothing rotational when effects.rotation is off.
#include "ratchet/observe/energy.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "state_at_rest.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

SceneDef two_spheres() {
  return build_scene(json::parse(R"({
    "name": "ke", "time": {"dt": 0.01, "duration": 1.0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]},
                             {"shape": "sphere", "radius": 1.0, "position": [3, 0, 1]}]}
  })"),
                     "ke.json");
}

State state_of(const SceneDef& s) { return test::state_at_rest(s); }

TEST(KineticEnergy, TranslationOfTheMovingBodies) {
  const SceneDef s = two_spheres();
  State st = state_of(s);
  EXPECT_EQ(kinetic_energy(s, st), 0.0);
  st.v[0] = Vec3(3.0, 0.0, 4.0);  // |v| = 5
  st.v[1] = Vec3(0.0, 2.0, 0.0);
  const double expected = 0.5 * s.bodies[0].mass * 25.0 + 0.5 * s.bodies[1].mass * 4.0;
  EXPECT_NEAR(kinetic_energy(s, st), expected, 1e-14 * expected);
}

TEST(KineticEnergy, FixedBodiesDoNotCount) {
  SceneDef s = two_spheres();
  State st = state_of(s);
  st.v[0] = Vec3(1.0, 0.0, 0.0);
  st.v[1] = Vec3(1.0, 0.0, 0.0);
  s.bodies[1].fixed = true;
  EXPECT_DOUBLE_EQ(kinetic_energy(s, st), 0.5 * s.bodies[0].mass);
}

TEST(KineticEnergy, RotationAtTheParticleScaleOnlyWithRotationOn) {
  SceneDef s = two_spheres();
  State st = state_of(s);
  s.bodies[1].fixed = true;
  st.w[0] = Vec3(0.0, 0.0, 2.0);
  st.s_p = 1.5;
  const double I = s.bodies[0].principal_inertia.z();
  ASSERT_GT(I, 0.0);
  s.effects.rotation = true;
  // A sphere's inertia is isotropic: 1/2 (s_p^2 I) |w|^2.
  EXPECT_NEAR(kinetic_energy(s, st), 0.5 * 1.5 * 1.5 * I * 4.0, 1e-14);
  s.effects.rotation = false;
  EXPECT_EQ(kinetic_energy(s, st), 0.0);
}

}  // namespace
}  // namespace ratchet

// Validation 1: the single expanding particle (docs/method.md s. 2 and "The step").
// A particle resting on the floor through heat, hold, cool, hold: its centre height must
// follow h0 (1 + alpha_p (T - T0)) because the expansion enters the contact kinematics as
// a velocity (docs/method.md), return to h0, and the kinetic energy must stay at the
// imposed expansion drift. A sphere jammed between walls must stay bounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/observe/energy.hpp"
#include "ratchet/world/world.hpp"
#include "support/check_record.hpp"

namespace ratchet {
namespace {

using validation::check_le;
using validation::check_near;
using validation::check_rel;

const std::string kDir = std::string(RATCHET_VALIDATION_DIR) + "/single_particle/";

struct HeightTrace {
  double h0 = 0.0;            // centre height when heating starts
  double max_rel_error = 0.0; // max |z - h0 s_p| / (h0 s_p) from then on
  double max_ke = 0.0;        // over the thermal protocol
  double z_end = 0.0;
  double ke_at_start = 0.0;
};

HeightTrace follow_height(const SceneDef& scene) {
  World world(scene);
  HeightTrace tr;
  const double t_start = scene.thermal.start_time;
  bool started = false;
  run_world(world, {}, [&](const World& w) {
    const State& s = w.state();
    if (!started) {
      if (s.t + 0.5 * scene.dt < t_start) return;
      started = true;
      tr.h0 = s.x[0].z() / s.s_p;
      tr.ke_at_start = kinetic_energy(w.scene(), w.state());
    }
    const double expected = tr.h0 * s.s_p;
    tr.max_rel_error = std::max(tr.max_rel_error, std::abs(s.x[0].z() - expected) / expected);
    tr.max_ke = std::max(tr.max_ke, kinetic_energy(w.scene(), w.state()));
    tr.z_end = s.x[0].z();
  });
  return tr;
}

void check_expanding_particle(const std::string& case_name, const std::string& file) {
  const SceneDef scene = load_scene(kDir + file);
  const HeightTrace tr = follow_height(scene);
  const BodyDef& b = scene.bodies[0];
  const double r = b.kind == ShapeKind::Sphere ? b.radius : 1.0;  // radius_range [1, 1] in the scene
  const double mgr = b.mass * 1.0 * r;                             // g = 1
  // The height is fixed by the normal constraints alone, which the exact kinematics
  // satisfy to round-off each step; 1e-6 is the brief's bound.
  EXPECT_TRUE(check_le(case_name, "max |z - h0 s_p| / (h0 s_p) over the cycle", tr.max_rel_error, 1e-6,
                       "expansion as a contact velocity keeps the height exact (brief: 1e-6)"));
  EXPECT_TRUE(check_rel(case_name, "centre height after the cycle / h0", tr.z_end / tr.h0, 1.0, 1e-6,
                        "s_p returns to 1 at T0"));
  // Slow ramps (dT/dt = 0.005) make the imposed drift (1/2) m (eps h0)^2 ~ 1e-13 m g r.
  EXPECT_TRUE(check_le(case_name, "max kinetic energy / (m g r) during the protocol", tr.max_ke / mgr, 1e-12,
                       "brief: 1e-12; the expansion drift alone is ~1e-13"));
  EXPECT_GT(tr.h0, 0.3);  // it did rest on the floor (not fallen through, not airborne)
}

TEST(SingleExpandingParticle, PolyhedronHeightFollowsExpansion) {
  check_expanding_particle("single particle: polyhedron", "polyhedron.json");
}

TEST(SingleExpandingParticle, SphereHeightFollowsExpansion) {
  check_expanding_particle("single particle: sphere", "sphere.json");
}

class JammedSphere : public ::testing::TestWithParam<double> {};

// What the jam tests watch: the total wall force in the hold at T1 (away from its ends),
// at the end, the kinetic energy and the steps stopped at the cap.
struct JamTrace {
  double force_hold_first = -1.0, force_hold_min = HUGE_VAL, force_hold_max = 0.0, force_end = -1.0, max_ke = 0.0;
  int unconverged_steps = 0;
  std::int64_t jammed_steps = 0;
};

JamTrace run_jam(const SceneDef& scene) {
  World world(scene);
  const ThermalProtocol& th = scene.thermal;
  const double hold_begin = th.heat_time, hold_end = th.heat_time + th.hold_time;
  JamTrace j;
  run_world(world, {}, [&](const World& w) {
    const double t = w.state().t;
    const double F = w.stats().wall_force_total;
    j.max_ke = std::max(j.max_ke, kinetic_energy(w.scene(), w.state()));
    j.unconverged_steps += w.stats().converged ? 0 : 1;
    if (t > hold_begin + 0.1 && t < hold_end - 0.1) {
      if (j.force_hold_first < 0.0) j.force_hold_first = F;
      j.force_hold_min = std::min(j.force_hold_min, F);
      j.force_hold_max = std::max(j.force_hold_max, F);
    }
    j.force_end = F;
  });
  j.jammed_steps = world.totals().jammed_steps;
  return j;
}

// A sphere growing into two fixed walls has no rigid solution: the sweeps hit
// max_iterations with the normal impulse growing with the sweep count. The step then
// yields to the jam (World::yield_to_jam): solved again without the imposed expansion
// and relaxation, the sphere keeps the overlap and no force is needed, since nothing
// loads it (no gravity). Before, the force was set by the cap, the same every step of
// the hold but meaningless. The kinetic energy must stay at the expansion drift
// (1/2) m (eps_p r)^2 and the force vanish once the sphere has shrunk back.
TEST_P(JammedSphere, YieldsWithoutForceAndKineticEnergyAtTheDrift) {
  const double p_gap = GetParam();
  const std::string case_name = "jammed sphere, p_gap = " + validation::format_number(p_gap);
  SceneDef scene = load_scene(kDir + "sphere_walls.json", {"solver.p_gap=" + validation::format_number(p_gap)});
  const ThermalProtocol& th = scene.thermal;
  const JamTrace j = run_jam(scene);
  const double eps = th.alpha_p * (th.T1 - th.T0) / th.heat_time;  // d s_p / dt on the ramps
  const double drift_ke = 0.5 * scene.bodies[0].mass * eps * eps;   // r = 1
  // The jam is real: it must show in the solver record.
  EXPECT_GT(j.unconverged_steps, 0);
  EXPECT_TRUE(validation::record(case_name, "steps solved as jams", static_cast<double>(j.jammed_steps), "> 0", "-",
                                 j.jammed_steps > 0, "the sphere outgrows the walls by 0.008: no rigid solution"));
  EXPECT_TRUE(check_near(case_name, "largest wall force during the hold", j.force_hold_max, 0.0, 0.0,
                         "no load presses the sphere (no gravity): the yielded step needs no force"));
  EXPECT_TRUE(check_near(case_name, "wall force after cooling back", j.force_end, 0.0, 0.0,
                         "the sphere is smaller than the gap again"));
  EXPECT_TRUE(check_le(case_name, "max kinetic energy / drift energy (1/2) m (eps r)^2", j.max_ke / drift_ke,
                       1.0 + 1e-6, "no energy beyond the imposed expansion drift"));
}

INSTANTIATE_TEST_SUITE_P(PGap, JammedSphere, ::testing::Values(0.01, 0.1, 1.0));

// With a contact compliance (docs/method.md s. 5) the same jam has a solution: the block
// W + c I is positive definite, so every step converges, and during the hold (nothing
// moves, u_n = 0) each wall's law u_n + b + c lambda_n = 0 gives the force in closed form:
// F = lambda_n / h = p_gap delta / (c h^2), c = epsilon W_nn = epsilon / m (a sphere
// pressed through its centre), delta = 0.01 - 0.002 the overlap at T1.
TEST(JammedSphereCompliant, EveryStepConvergesAndTheHoldForceIsTheCompliantLaw) {
  const double epsilon = 0.03;
  // The squeeze (both walls pressing alike) is a self-stress: Gauss-Seidel contracts it
  // by about 1 - epsilon per sweep, so the tolerance 1e-8 takes some 600 sweeps here.
  SceneDef scene = load_scene(kDir + "sphere_walls.json", {"solver.compliance=0.03", "solver.max_iterations=5000"});
  const ThermalProtocol& th = scene.thermal;
  const JamTrace j = run_jam(scene);
  const double force_hold_min = j.force_hold_min, force_hold_max = j.force_hold_max, force_end = j.force_end,
               max_ke = j.max_ke;
  const int unconverged_steps = j.unconverged_steps;
  const std::string case_name = "jammed sphere, compliance 0.03";
  const double m = scene.bodies[0].mass, h = scene.dt, p_gap = scene.solver.p_gap;
  const double delta = th.alpha_p * (th.T1 - th.T0) * 1.0 - 0.002;  // r = 1
  const double per_wall = p_gap * delta / (epsilon / m * h * h);
  EXPECT_TRUE(check_near(case_name, "steps stopped at the cap", unconverged_steps, 0.0, 0.0,
                         "W + c I is positive definite: the compliant problem always has a solution"));
  EXPECT_TRUE(check_rel(case_name, "wall force during the hold, both walls", force_hold_max, 2.0 * per_wall, 1e-6,
                        "F = p_gap delta / (c h^2) per wall; 1e-6: the tolerance 1e-8 of the solve and round-off"));
  EXPECT_TRUE(check_rel(case_name, "min / max wall force during the hold", force_hold_min / force_hold_max, 1.0, 1e-6,
                        "nothing moves during the hold: the force is steady"));
  EXPECT_TRUE(check_near(case_name, "wall force after cooling back", force_end, 0.0, 0.0,
                         "the sphere is smaller than the gap again"));
  const double eps = th.alpha_p * (th.T1 - th.T0) / th.heat_time;
  EXPECT_TRUE(check_le(case_name, "max kinetic energy / drift energy (1/2) m (eps r)^2",
                       max_ke / (0.5 * m * eps * eps), 1.0 + 1e-6, "no energy beyond the imposed expansion drift"));
}

}  // namespace
}  // namespace ratchet

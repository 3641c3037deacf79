// The rigid law's stall fallback: the accelerated projected gradient on problems with a
// known answer (column_problem.hpp), against Gauss-Seidel, and its switch in solve_nsgs.
#include "ratchet/solver/apgd.hpp"

#include <gtest/gtest.h>

#include "column_problem.hpp"
#include "ratchet/solver/nsgs.hpp"

namespace ratchet {
namespace {

SolveSettings settings(int cap, double tol, bool friction) { return test::column_settings(cap, tol, friction, true); }

TEST(Apgd, ColumnCarriesTheWeightOfEverythingAbove) {
  test::Column c(30, 0.04, 0.0);
  SolverBodies b = c.bodies();
  const ApgdResult r = solve_apgd(c.rows, b, settings(100000, 1e-10, true), c.scratch, 100000);
  ASSERT_TRUE(r.converged);
  EXPECT_LT(r.residual, 1e-10);
  for (int k = 0; k < c.n; ++k) {
    // The natural-map residual bounds the impulses' error by about cond(W) ~ n^2 = 900
    // times it: 1e-10 x 900 on the scale n g h, with room.
    EXPECT_NEAR(c.rows[static_cast<std::size_t>(k)].lambda[0], (c.n - k) * c.gh, 1e-6 * c.n * c.gh) << k;
    EXPECT_NEAR(c.v[static_cast<std::size_t>(k)].z(), 0.0, 1e-6) << k;
  }
}

// The reason for the method: Gauss-Seidel carries a deep column's load down about one
// contact per sweep and needs of the order of n^2 sweeps; the accelerated gradient of
// the order of n (Nesterov's rate, sqrt of the condition number ~ n^2).
TEST(Apgd, ADeepColumnTakesFewerStepsThanPlainSweeps) {
  test::Column g(60, 0.04, 0.0), a(60, 0.04, 0.0);
  SolverBodies bg = g.bodies(), ba = a.bodies();
  const SolveResult rg = solve_nsgs(g.rows, bg, settings(1000000, 1e-8, false), g.scratch);
  const ApgdResult ra = solve_apgd(a.rows, ba, settings(1000000, 1e-8, false), a.scratch, 1000000);
  ASSERT_TRUE(rg.converged);
  ASSERT_TRUE(ra.converged);
  EXPECT_LT(ra.iterations, rg.sweeps / 3) << "APGD " << ra.iterations << " steps, Gauss-Seidel " << rg.sweeps;
}

// A column sliding over a rough floor: the floor's friction brakes the whole column
// through the sticking contacts above it, a frictional problem with one answer. Both
// methods solved tightly agree, and the gradient's answer satisfies Coulomb's law.
TEST(Apgd, ASlidingColumnAgreesWithGaussSeidel) {
  const double mu = 0.3;
  test::Column g(8, 0.04, mu), a(8, 0.04, mu);
  for (test::Column* c : {&g, &a}) {
    for (Vec3& v : c->v) v.x() = 0.5;
    c->scratch.v_free = c->v;
  }
  SolverBodies bg = g.bodies(), ba = a.bodies();
  ASSERT_TRUE(solve_nsgs(g.rows, bg, settings(1000000, 1e-12, true), g.scratch).converged);
  const ApgdResult ra = solve_apgd(a.rows, ba, settings(1000000, 1e-10, true), a.scratch, 1000000);
  ASSERT_TRUE(ra.converged);
  EXPECT_LT(coulomb_residual(a.rows, ba, false), 1e-10);
  // The floor contact slides: its friction is on the cone, against the motion (to 1e-8,
  // a hundred times the residual 1e-10 on impulses of order n g h = 0.3).
  EXPECT_NEAR(a.rows[0].lambda[1], -mu * a.rows[0].lambda[0], 1e-8);
  // 1e-6: the two stopping rules (1e-12 per sweep, 1e-10 natural map) leave each answer
  // within cond(W) ~ n^2 = 64 times its residual of the exact one.
  for (std::size_t k = 0; k < a.rows.size(); ++k)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.rows[k].lambda[j], g.rows[k].lambda[j], 1e-6) << k << " " << j;
}

TEST(Apgd, CoulombResidualIsZeroAtTheAnswerOnly) {
  test::Column c(5, 0.04, 0.5);
  SolverBodies b = c.bodies();
  const double cold = coulomb_residual(c.rows, b, false);
  // No impulse, every body falling into the one below: the residual is then the absolute
  // norm of P_K(-rho u), about g h for the floor contact alone.
  EXPECT_GT(cold, 0.5 * c.gh);
  ASSERT_TRUE(solve_nsgs(c.rows, b, settings(100000, 1e-13, true), c.scratch).converged);
  // 1e-9: the sweeps' change criterion 1e-13 leaves a residual a few thousand times it
  // at most on a 5-deep column (its slow mode); a wrong answer is of order 1.
  EXPECT_LT(coulomb_residual(c.rows, b, false), 1e-9);
}

// solve_nsgs hands a stalled rigid solve to the gradient method when asked: plain sweeps
// on a deep column halve their residual too slowly for a patience of 5 sweeps.
TEST(Apgd, AStalledRigidSolveGoesOnByTheGradient) {
  test::Column c(60, 0.04, 0.0), off(60, 0.04, 0.0);
  SolveSettings s = settings(100000, 1e-9, false);
  s.stall_sweeps = 5;
  s.apgd_fallback = true;
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, s, c.scratch);
  ASSERT_TRUE(r.converged);
  EXPECT_GT(r.apgd_iterations, 0);
  EXPECT_GE(r.sweeps - r.apgd_iterations, 10);  // the sweeps before the switch: two patiences at least
  EXPECT_LT(r.sweeps, 100000);
  // 1e-5 of the largest impulse: the residual 1e-9 times cond(W) ~ n^2 = 3600, with room.
  for (int k = 0; k < c.n; ++k)
    EXPECT_NEAR(c.rows[static_cast<std::size_t>(k)].lambda[0], (c.n - k) * c.gh, 1e-5 * c.n * c.gh) << k;
  // Without the fallback the same solve does not switch.
  s.apgd_fallback = false;
  SolverBodies bo = off.bodies();
  EXPECT_EQ(solve_nsgs(off.rows, bo, s, off.scratch).apgd_iterations, 0);
}

}  // namespace
}  // namespace ratchet

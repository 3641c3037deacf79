// The rigid law's stall fallback: the accelerated projected gradient on problems with a
// known answer (column_problem.hpp), against Gauss-Seidel, and its switch in solve_nsgs.
#include "ratchet/solver/apgd.hpp"

#include <gtest/gtest.h>
#include <omp.h>


#include "column_problem.hpp"
#include "ratchet/solver/nsgs.hpp"
#include "ratchet/solver/row_colouring.hpp"

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

// The gradient's passes split among threads give the same bits for 1, 2, 3 and 8
// threads, and the same as one thread in row order without a colouring: a column of 3000
// bodies sliding over a rough floor (rows enough to split; the chain takes two colours,
// as World colours its contacts), 300 gradient steps from a cold start, far from
// converged so that every pass keeps changing the answer.
TEST(Apgd, TheSameBitsOnAnyNumberOfThreads) {
  const int saved_threads = omp_get_max_threads();
  auto column = [] {
    test::Column c(3000, 0.04, 0.3);
    for (Vec3& v : c.v) v.x() = 0.5;
    c.scratch.v_free = c.v;
    return c;
  };
  test::Column base = column();
  std::vector<int> a, b, perm;
  for (const SolverRow& r : base.rows) {
    a.push_back(r.a);
    b.push_back(r.b);
  }
  RowColouring colouring;
  colour_rows(a, b, std::vector<bool>(base.v.size(), true), perm, colouring);
  ASSERT_EQ(colouring.colours(), 2);
  auto bits = [](const test::Column& c) {
    std::string out;
    for (const SolverRow& r : c.rows) out.append(reinterpret_cast<const char*>(r.lambda.data()), sizeof(Vec3));
    out.append(reinterpret_cast<const char*>(c.v.data()), c.v.size() * sizeof(Vec3));
    return out;
  };
  auto solve = [&](int threads, bool coloured) {
    test::Column c = column();
    std::vector<SolverRow> rows;
    for (int k : perm) rows.push_back(c.rows[static_cast<std::size_t>(k)]);
    c.rows = rows;
    SolveSettings s = settings(300, 1e-12, true);
    s.colouring = coloured ? &colouring : nullptr;
    s.parallel_min_rows = coloured ? 0 : 1 << 30;
    omp_set_num_threads(threads);
    SolverBodies bodies = c.bodies();
    const ApgdResult r = solve_apgd(c.rows, bodies, s, c.scratch, 300);
    EXPECT_EQ(r.iterations, 300);
    EXPECT_FALSE(r.converged);
    return bits(c);
  };
  const std::string serial = solve(1, false);
  for (int threads : {1, 2, 3, 8}) EXPECT_TRUE(solve(threads, true) == serial) << threads << " threads";
  omp_set_num_threads(saved_threads);
}

}  // namespace
}  // namespace ratchet

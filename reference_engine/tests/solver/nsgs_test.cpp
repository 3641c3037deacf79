// The global Gauss-Seidel solve on a problem with a known answer (column_problem.hpp).
#include "ratchet/solver/nsgs.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "column_problem.hpp"

namespace ratchet {
namespace {

SolveSettings settings(int cap, double tol, bool friction) { return test::column_settings(cap, tol, friction); }

TEST(Nsgs, ColumnCarriesTheWeightOfEverythingAbove) {
  test::Column c(10, 0.04, 0.5);
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, settings(100000, 1e-12, true), c.scratch);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.sweeps, 10);  // the load travels about one contact per sweep
  for (int k = 0; k < c.n; ++k) {
    // 1e-9 of the largest impulse: the tolerance 1e-12 on the relative sweep change
    // leaves at most a few hundred times that in the slow mode.
    EXPECT_NEAR(c.rows[static_cast<std::size_t>(k)].lambda[0], (c.n - k) * c.gh, 1e-9 * c.n * c.gh) << k;
    // Everything at rest: a body's velocity is its contacts' impulse error (unit mass).
    EXPECT_NEAR(c.v[static_cast<std::size_t>(k)].z(), 0.0, 1e-9) << k;
  }
}

TEST(Nsgs, StopsAtTheCapAndSaysItDidNotConverge) {
  test::Column c(30, 0.04, 0.0);
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, settings(5, 1e-10, false), c.scratch);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.sweeps, 5);
  EXPECT_GT(r.residual, 1e-10);
}

TEST(Nsgs, VelocityCriterionMeasuresTheBodiesNotTheImpulses) {
  test::Column c(10, 0.04, 0.5);
  SolverBodies b = c.bodies();
  SolveSettings s = settings(100000, 1e-10, true);
  s.by_velocity = true;
  const SolveResult r = solve_nsgs(c.rows, b, s, c.scratch);
  EXPECT_TRUE(r.converged);
  // The velocity residual is the sweep's change of the velocities in the kinetic-energy
  // norm, relative to all the contacts changed: at convergence the column is at rest.
  // 1e-8: the velocity residual 1e-10 is relative to the contacts' whole velocity change
  // (0.04 per body here), summed over 10 bodies.
  for (int k = 0; k < c.n; ++k) EXPECT_NEAR(c.v[static_cast<std::size_t>(k)].z(), 0.0, 1e-8) << k;
}

// Compliance (docs/method.md s. 5): every contact's law holds for u + c lambda with
// c = epsilon W_nn, the block W + c I in the local solve: its inverse in the rows, epsilon
// in the settings.
void make_compliant(test::Column& c, double epsilon) {
  for (SolverRow& r : c.rows) {
    Mat3 Wc = r.W;
    Wc.diagonal().array() += row_compliance(r, epsilon);
    r.W_inv = Wc.inverse();
  }
}
SolveSettings with_compliance(SolveSettings s, double epsilon) {
  s.compliance = epsilon;
  return s;
}

// The compliant column has a known answer too: with every contact pressed, body k
// (unit mass) leaves with v_k = -g h + l_k - l_{k+1}, and each contact's normal law is
// the equality u_n + c l = 0, a tridiagonal system solved here directly.
TEST(Nsgs, CompliantColumnSolvesTheCompliantLaw) {
  const double epsilon = 0.1;
  test::Column c(10, 0.04, 0.5);
  make_compliant(c, epsilon);
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, with_compliance(settings(100000, 1e-13, true), epsilon), c.scratch);
  ASSERT_TRUE(r.converged);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(c.n, c.n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(c.n);
  for (int k = 0; k < c.n; ++k) {
    const double ck = row_compliance(c.rows[static_cast<std::size_t>(k)], epsilon);
    A(k, k) = (k == 0 ? 1.0 : 2.0) + ck;  // u_n = v_k - v_{k-1} (v_0 against the floor)
    if (k > 0) A(k, k - 1) = -1.0;
    if (k + 1 < c.n) A(k, k + 1) = -1.0;
  }
  rhs(0) = c.gh;  // the floor contact: -g h + l_0 - l_1 + c l_0 = 0
  const Eigen::VectorXd exact = A.partialPivLu().solve(rhs);
  for (int k = 0; k < c.n; ++k) {
    ASSERT_GT(exact(k), 0.0) << k;  // every contact pressed, as the system assumes
    // 1e-9 of the largest impulse: the compliant problem is well conditioned, and the
    // tolerance 1e-13 leaves far less than that.
    EXPECT_NEAR(c.rows[static_cast<std::size_t>(k)].lambda[0], exact(k), 1e-9 * c.n * c.gh) << k;
    // No tangential load at all: what is left is round-off of impulses of order 0.4.
    EXPECT_NEAR(c.rows[static_cast<std::size_t>(k)].lambda[1], 0.0, 1e-12) << k;
  }
  // Not the rigid answer: the compliant floor carries less than the whole weight in
  // this step (the column sinks by c l h into it instead).
  EXPECT_LT(c.rows[0].lambda[0], 0.99 * c.n * c.gh);
  // The accelerated sweeps reach the same compliant answer (the tiers' combination).
  test::Column fast(10, 0.04, 0.5);
  make_compliant(fast, epsilon);
  SolverBodies bf = fast.bodies();
  SolveSettings sf = with_compliance(settings(100000, 1e-13, true), epsilon);
  sf.anderson_depth = 5;
  ASSERT_TRUE(solve_nsgs(fast.rows, bf, sf, fast.scratch).converged);
  for (int k = 0; k < c.n; ++k)
    EXPECT_NEAR(fast.rows[static_cast<std::size_t>(k)].lambda[0], exact(k), 1e-9 * c.n * c.gh) << k;
  // Zero compliance is the rigid law, bit for bit: W + 0 I is W.
  test::Column rigid(10, 0.04, 0.5), zero(10, 0.04, 0.5);
  make_compliant(zero, 0.0);
  SolverBodies br = rigid.bodies(), bz = zero.bodies();
  (void)solve_nsgs(rigid.rows, br, settings(100000, 1e-10, true), rigid.scratch);
  (void)solve_nsgs(zero.rows, bz, settings(100000, 1e-10, true), zero.scratch);
  for (int k = 0; k < c.n; ++k)
    EXPECT_EQ(rigid.rows[static_cast<std::size_t>(k)].lambda, zero.rows[static_cast<std::size_t>(k)].lambda) << k;
}

// Why compliance is fast: the rigid column's slow mode takes O(n^2) sweeps, while the
// compliant operator W + c I has a condition number at most (sigma_max + c) / c, so
// its sweep count does not grow with the depth of the column.
TEST(Nsgs, CompliantSweepCountDoesNotGrowWithDepth) {
  auto sweeps = [](int n, double epsilon) {
    test::Column c(n, 0.04, 0.0);
    make_compliant(c, epsilon);
    SolverBodies b = c.bodies();
    const SolveResult r = solve_nsgs(c.rows, b, with_compliance(settings(1000000, 1e-8, false), epsilon), c.scratch);
    EXPECT_TRUE(r.converged) << n << " " << epsilon;
    return r.sweeps;
  };
  const int rigid20 = sweeps(20, 0.0), rigid40 = sweeps(40, 0.0);
  const int soft20 = sweeps(20, 0.1), soft40 = sweeps(40, 0.1);
  EXPECT_GT(rigid40, 3 * rigid20);  // O(n^2): doubling the depth about quadruples it
  EXPECT_LT(soft40, 2 * soft20);    // bounded by the conditioning, not the depth
  EXPECT_LT(5 * soft40, rigid40);
}

// Stall guard (docs/method.md): a compliant solve whose plain sweeps stall too is
// relaxed, halving down to 0.25. Forced here by a patience of one sweep (the plain
// sweeps on a column rarely halve the residual in one): relaxation slows a contracting
// solve but keeps its fixed point, and the rigid law is never relaxed.
TEST(Nsgs, AStalledCompliantSolveIsRelaxedAndKeepsItsAnswer) {
  const double epsilon = 0.1;
  auto solve = [&](double eps, int patience, SolveResult& r) {
    test::Column c(20, 0.04, 0.5);
    make_compliant(c, eps);
    SolverBodies b = c.bodies();
    SolveSettings s = with_compliance(settings(1000000, 1e-12, true), eps);
    s.stall_sweeps = patience;
    r = solve_nsgs(c.rows, b, s, c.scratch);
    return c;
  };
  SolveResult calm, stalled;
  const test::Column ref = solve(epsilon, 100, calm);
  const test::Column relaxed = solve(epsilon, 1, stalled);
  ASSERT_TRUE(calm.converged);
  ASSERT_TRUE(stalled.converged);
  EXPECT_EQ(calm.relaxation, 1.0);
  EXPECT_EQ(stalled.relaxation, 0.25);   // relaxed twice, then no further
  EXPECT_GT(stalled.sweeps, calm.sweeps);  // a quarter of each step: a slower contraction
  for (std::size_t k = 0; k < ref.rows.size(); ++k) {
    // The same compliant answer: the tolerance 1e-12 on the sweep's change bounds both
    // solves' distance to it far below 1e-9 of the largest impulse (n g h = 0.8).
    EXPECT_NEAR(relaxed.rows[k].lambda[0], ref.rows[k].lambda[0], 1e-9 * 20 * 0.04) << k;
    // No tangential load at all: round-off of impulses of order 0.8.
    EXPECT_NEAR(relaxed.rows[k].lambda[1], 0.0, 1e-12) << k;
  }
  SolveResult rigid;
  (void)solve(0.0, 1, rigid);
  EXPECT_TRUE(rigid.plain_fallback);
  EXPECT_EQ(rigid.relaxation, 1.0);  // the rigid law is left to its jam tests
}

TEST(Nsgs, NoRowsIsConvergedWithNoSweep) {
  test::Column c(3, 0.04, 0.5);
  c.rows.clear();
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, settings(100, 1e-4, true), c.scratch);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.sweeps, 0);
}

// Energy-safe relaxation on a compliant row (docs/method.md s. 5): the capped speed is a
// second law, and the row takes the solution that pushes less. One unit mass on the
// floor (W = 1), compliance c = 0.1, an overlap that asks for the speed 5.
struct PushCase {
  double lambda, v;
};
PushCase push_off_the_floor(double g_h, double cap, bool friction) {
  test::Column c(1, g_h, friction ? 0.5 : 0.0);
  make_compliant(c, 0.1);
  c.rows[0].bias = -5.0;
  c.rows[0].bias_capped = cap > 0.0 ? -cap : 0.0;
  SolverBodies b = c.bodies();
  const SolveResult r = solve_nsgs(c.rows, b, with_compliance(settings(100, 1e-14, friction), 0.1), c.scratch);
  EXPECT_TRUE(r.converged);
  return {c.rows[0].lambda[0], c.v[0].z()};
}

TEST(Nsgs, AnUnloadedCompliantOverlapLeavesAtTheCappedSpeed) {
  for (bool friction : {false, true}) {
    // Spring law alone: lambda = (5 + gh) / 1.1, u = 5 - 0.1 lambda = 4.58.
    // 1e-12: one contact, solved exactly by the local law; the sweep stops at 1e-14.
    const PushCase free = push_off_the_floor(0.04, 0.0, friction);
    EXPECT_NEAR(free.v, 5.0 - 0.1 * 5.04 / 1.1, 1e-12);
    // Capped at 0.5: the rigid law u = 0.5 pushes less (lambda 0.54 < 4.58).
    const PushCase capped = push_off_the_floor(0.04, 0.5, friction);
    EXPECT_NEAR(capped.v, 0.5, 1e-12) << friction;
    EXPECT_NEAR(capped.lambda, 0.54, 1e-12) << friction;
  }
}

TEST(Nsgs, ALoadedCompliantOverlapKeepsTheSpringLawBitForBit) {
  for (bool friction : {false, true}) {
    // Load gh = 100: the spring's lambda = 105 / 1.1 = 95.5 (u = 5 - 9.55 < 0: still
    // compressing) is below the capped law's 100.5, so the cap does not bind and the
    // bits are the spring's.
    const PushCase spring = push_off_the_floor(100.0, 0.0, friction);
    const PushCase capped = push_off_the_floor(100.0, 0.5, friction);
    EXPECT_LT(spring.v, 0.5);
    EXPECT_EQ(spring.lambda, capped.lambda) << friction;
    EXPECT_EQ(spring.v, capped.v) << friction;
  }
}

}  // namespace
}  // namespace ratchet

// The global Gauss-Seidel solve on a problem with a known answer (column_problem.hpp).
#include "ratchet/solver/nsgs.hpp"

#include <gtest/gtest.h>

#include "column_problem.hpp"

namespace ratchet {
namespace {

NsgsSettings settings(int cap, double tol, bool friction) {
  NsgsSettings s;
  s.max_iterations = cap;
  s.tolerance = tol;
  s.friction = friction;
  s.rotation = false;
  return s;
}

TEST(Nsgs, ColumnCarriesTheWeightOfEverythingAbove) {
  test::Column c(10, 0.04, 0.5);
  SolverBodies b = c.bodies();
  const NsgsResult r = solve_nsgs(c.rows, b, settings(100000, 1e-12, true), c.scratch);
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
  const NsgsResult r = solve_nsgs(c.rows, b, settings(5, 1e-10, false), c.scratch);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.sweeps, 5);
  EXPECT_GT(r.residual, 1e-10);
}

TEST(Nsgs, VelocityCriterionMeasuresTheBodiesNotTheImpulses) {
  test::Column c(10, 0.04, 0.5);
  SolverBodies b = c.bodies();
  NsgsSettings s = settings(100000, 1e-10, true);
  s.by_velocity = true;
  const NsgsResult r = solve_nsgs(c.rows, b, s, c.scratch);
  EXPECT_TRUE(r.converged);
  // The velocity residual is the sweep's change of the velocities in the kinetic-energy
  // norm, relative to all the contacts changed: at convergence the column is at rest.
  // 1e-8: the velocity residual 1e-10 is relative to the contacts' whole velocity change
  // (0.04 per body here), summed over 10 bodies.
  for (int k = 0; k < c.n; ++k) EXPECT_NEAR(c.v[static_cast<std::size_t>(k)].z(), 0.0, 1e-8) << k;
}

TEST(Nsgs, NoRowsIsConvergedWithNoSweep) {
  test::Column c(3, 0.04, 0.5);
  c.rows.clear();
  SolverBodies b = c.bodies();
  const NsgsResult r = solve_nsgs(c.rows, b, settings(100, 1e-4, true), c.scratch);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.sweeps, 0);
}

}  // namespace
}  // namespace ratchet

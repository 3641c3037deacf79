// Anderson acceleration of the sweeps: the same fixed point as plain Gauss-Seidel, in
// fewer sweeps on the slow mode of a deep column, and every iterate inside the cones.
#include "ratchet/solver/anderson.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "column_problem.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

SolveSettings settings(int depth, int max_iterations = 100000, double tolerance = 1e-10) {
  SolveSettings s;
  s.max_iterations = max_iterations;
  s.tolerance = tolerance;
  s.rotation = false;
  s.anderson_depth = depth;
  return s;
}

TEST(Anderson, SameImpulsesAsPlainSweepsInFarFewerSweeps) {
  test::Column plain(40, 0.04, 0.5), fast(40, 0.04, 0.5);
  SolverBodies bp = plain.bodies(), bf = fast.bodies();
  const SolveResult rp = solve_nsgs(plain.rows, bp, settings(0), plain.scratch);
  const SolveResult rf = solve_nsgs(fast.rows, bf, settings(5), fast.scratch);
  ASSERT_TRUE(rp.converged);
  ASSERT_TRUE(rf.converged);
  // Plain sweeps need O(n^2) on a column of n; the acceleration must cut that at least
  // fourfold here, or it is not worth its cost per sweep.
  EXPECT_LT(4 * rf.sweeps, rp.sweeps) << rf.sweeps << " against " << rp.sweeps;
  // 1e-7 of the largest impulse: the sweep tolerance 1e-10 leaves the accelerated
  // iterate within a few hundred times that of the fixed point (its slow mode is damped,
  // not gone), far below the per-contact load step gh = 0.04.
  for (int k = 0; k < plain.n; ++k) {
    const double exact = (plain.n - k) * plain.gh;
    EXPECT_NEAR(fast.rows[static_cast<std::size_t>(k)].lambda[0], exact, 1e-7 * plain.n * plain.gh) << k;
    EXPECT_NEAR(fast.v[static_cast<std::size_t>(k)].z(), 0.0, 1e-7) << k;
  }
}

TEST(Anderson, MixedImpulsesStayInsideTheirCones) {
  test::Column c(20, 0.04, 0.3);
  std::vector<SolverRow> rows = c.rows;
  AndersonBuffers buffers;
  AndersonMixer mixer(buffers, 4);
  Rng rng(7);
  int mixes = 0;
  // Sweep outputs inside the cones but jumping about (as a flowing bed's contacts do):
  // their extrapolation leaves the cones and must be projected back.
  for (int pass = 0; pass < 12; ++pass) {
    // A made-up sweep, recorded as solve_nsgs records a real one.
    double* x = mixer.record_buffer(rows.size(), false);
    double* g = mixer.record_buffer(rows.size(), true);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      SolverRow& r = rows[k];
      const double ln = uniform(rng, 0.0, 1.0), phi = uniform(rng, 0.0, 6.283185307179586);
      const double lt = r.mu * ln * uniform(rng, 0.5, 1.0);
      for (int j = 0; j < 3; ++j) x[3 * k + static_cast<std::size_t>(j)] = r.lambda[j];
      r.lambda = Vec3(ln, lt * std::cos(phi), lt * std::sin(phi));
      for (int j = 0; j < 3; ++j) g[3 * k + static_cast<std::size_t>(j)] = r.lambda[j];
    }
    if (mixer.plan(rows)) {
      ++mixes;
      for (std::size_t k = 0; k < rows.size(); ++k) rows[k].lambda = mixer.extrapolated(k, rows[k].mu);
    }
    for (const SolverRow& r : rows) {
      EXPECT_GE(r.lambda[0], 0.0);
      // 1e-12 relative: the projection scales lambda_t by cap / |lambda_t|, exact up to
      // a few roundings of hypot; 1e-300 admits the open contact (0 <= 0).
      EXPECT_LE(std::hypot(r.lambda[1], r.lambda[2]), r.mu * r.lambda[0] * (1.0 + 1e-12) + 1e-300);
    }
  }
  EXPECT_GT(mixes, 0);
}

// The mixer's arrays are kept in the solve's scratch from step to step: a solve after
// another one, on a smaller problem, gives the bits of a solve with fresh arrays.
TEST(Anderson, KeptBuffersGiveTheBitsOfFreshOnes) {
  // Solved to 1e-8 so that each solve runs many sweeps on its arrays; the
  // comparison itself is exact.
  test::Column first(40, 0.04, 0.5), kept(25, 0.03, 0.4), fresh(25, 0.03, 0.4);
  SolverBodies b1 = first.bodies();
  ASSERT_TRUE(solve_nsgs(first.rows, b1, settings(5, 100000, 1e-8), first.scratch).converged);
  first.scratch.v_free = kept.scratch.v_free;
  first.scratch.w_free = kept.scratch.w_free;
  SolverBodies bk = kept.bodies(), bf = fresh.bodies();
  const SolveResult rk = solve_nsgs(kept.rows, bk, settings(5, 100000, 1e-8), first.scratch);
  const SolveResult rf = solve_nsgs(fresh.rows, bf, settings(5, 100000, 1e-8), fresh.scratch);
  EXPECT_EQ(rk.sweeps, rf.sweeps);
  EXPECT_EQ(rk.residual, rf.residual);
  for (std::size_t k = 0; k < kept.rows.size(); ++k)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(kept.rows[k].lambda[j], fresh.rows[k].lambda[j]) << k;
}

// A rigid jam: a unit mass between a floor and a ceiling that both ask it to move away
// at speed kJamSpeed (biases -kJamSpeed), i.e. u_z >= a and -u_z >= a: no solution. Each
// plain sweep adds the same impulse 2a to both contacts. The column of one body, at rest,
// with a ceiling row: the floor's row with its normal and second tangent turned over.
constexpr double kJamSpeed = 0.01;
test::Column jam_problem() {
  test::Column c(1, 0.0, 0.0);
  SolverRow ceiling = c.rows[0];
  ceiling.b = wall_side(1);
  ceiling.F.col(0) = -Vec3::UnitZ();
  ceiling.F.col(2) = -Vec3::UnitY();
  c.rows.push_back(ceiling);
  for (SolverRow& r : c.rows) r.bias = -kJamSpeed;
  return c;
}

// The scene defaults' cap and tolerance, frictionless: the jam's sweeps are those of a scene.
SolveSettings jam_settings(bool rigid) {
  const SolverSettings defaults;
  SolveSettings s = settings(5, defaults.max_iterations, defaults.tolerance);
  s.friction = false;
  s.rigid = rigid;
  return s;
}

TEST(Anderson, UnboundedItExtrapolatesAJamToImpulsesThatLookConverged) {
  // Why the rigid law bounds the step: without the bound the solve reports convergence
  // at impulses set by the extrapolation, some hundred million increments of the jam.
  test::Column j = jam_problem();
  SolverBodies b = j.bodies();
  const SolveResult r = solve_nsgs(j.rows, b, jam_settings(false), j.scratch);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(normal_impulse_sum(j.rows), 1e8 * 2.0 * kJamSpeed) << r.sweeps << " sweeps";
}

TEST(Anderson, BoundedWithTheRigidLawAJamIsSeenAndItsImpulsesStayFinite) {
  test::Column j = jam_problem();
  SolverBodies b = j.bodies();
  const SolveResult r = solve_nsgs(j.rows, b, jam_settings(true), j.scratch);
  EXPECT_TRUE(r.normal_growth || r.persistent_growth) << r.sweeps << " sweeps, converged " << r.converged;
  // At most the plain increment 2a plus 100 of them (the bound) per sweep and contact.
  EXPECT_LE(normal_impulse_sum(j.rows), 2.0 * r.sweeps * 101.0 * 2.0 * kJamSpeed);
}

TEST(Anderson, TheRigidBoundLeavesASolvableColumnToConvergeAsFast) {
  // The deep column is solvable: its extrapolation stays within the bound's 100 sweeps'
  // worth, or the bound must not cost more than a few sweeps.
  test::Column free(40, 0.04, 0.5), bounded(40, 0.04, 0.5);
  SolverBodies bf = free.bodies(), bb = bounded.bodies();
  SolveSettings rigid = settings(5);
  rigid.rigid = true;
  const SolveResult rf = solve_nsgs(free.rows, bf, settings(5), free.scratch);
  const SolveResult rb = solve_nsgs(bounded.rows, bb, rigid, bounded.scratch);
  ASSERT_TRUE(rb.converged);
  EXPECT_FALSE(rb.persistent_growth);
  EXPECT_LE(rb.sweeps, rf.sweeps + 5) << rb.sweeps << " against " << rf.sweeps;
}

}  // namespace
}  // namespace ratchet

// Anderson acceleration of the sweeps: the same fixed point as plain Gauss-Seidel, in
// fewer sweeps on the slow mode of a deep column, and every iterate inside the cones.
#include "ratchet/solver/anderson.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "column_problem.hpp"
#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

SolveSettings settings(int depth) {
  SolveSettings s;
  s.max_iterations = 100000;
  s.tolerance = 1e-10;
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
  AndersonMixer mixer(4);
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

}  // namespace
}  // namespace ratchet

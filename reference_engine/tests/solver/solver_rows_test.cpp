// What every global solve shares (solver/solver_rows.hpp): the kernels keep a contact's
// local velocity and its bodies' velocities consistent, and the jam detector fires only
// on an unconverged solve whose normal impulses still grew.
#include "ratchet/solver/solver_rows.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace ratchet {
namespace {

TEST(SolverRows, AnImpulseChangesTheLocalVelocityByWTimesIt) {
  // Two unit masses, no rotation, the identity frame (n = x): W = (1/m_a + 1/m_b) I = 2 I.
  std::vector<Vec3> v = {Vec3(0, 0, -1), Vec3(0, 0, 1)}, w(2, Vec3::Zero());
  const std::vector<double> inv_mass = {1.0, 1.0};
  const std::vector<Mat3> inv_inertia(2, Mat3::Zero());
  const BodyArrays B{v.data(), w.data(), inv_mass.data(), inv_inertia.data()};
  SolverRow r;
  r.a = 0;
  r.b = 1;
  const Vec3 before = local_velocity(r, B, false);
  EXPECT_EQ(before, Vec3(0, 0, -2));
  apply_local_impulse(r, Vec3(0.25, 0.5, 0.0), B, false);
  EXPECT_EQ(local_velocity(r, B, false) - before, Vec3(0.5, 1.0, 0.0));  // exact in binary
  EXPECT_EQ(v[0] + v[1], Vec3(0, 0, 0));  // momentum kept: equal and opposite
}

TEST(SolverRows, TheNormalVelocityAloneHasTheBitsOfTheLocalVelocitysFirstComponent) {
  // The sweep decides an unloaded row by normal_velocity; it must be local_velocity()[0]
  // to the last bit, for a wall partner too, with and without rotation.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto vec = [&] {
    const double x = unit(rng), y = unit(rng), z = unit(rng), size = std::pow(10.0, 3.0 * unit(rng));
    return Vec3(x * size, y * size, z * size);
  };
  std::vector<Vec3> v(2), w(2);
  const std::vector<double> inv_mass = {1.0, 1.0};
  const std::vector<Mat3> inv_inertia(2, Mat3::Zero());
  const BodyArrays B{v.data(), w.data(), inv_mass.data(), inv_inertia.data()};
  int compared = 0;
  for (int k = 0; k < 20000; ++k) {
    SolverRow r;
    r.a = 0;
    r.b = k % 4 == 0 ? wall_side(2) : 1;
    for (int c = 0; c < 3; ++c) {
      const Vec3 f = vec(), ja = vec(), jb = vec();
      for (int i = 0; i < 3; ++i) {
        r.F(i, c) = f[i];
        r.Ja(c, i) = ja[i];
        r.Jb(c, i) = jb[i];
      }
    }
    r.u0 = vec();
    v = {vec(), vec()};
    w = {vec(), vec()};
    for (bool rotation : {false, true}) {
      const double full = local_velocity(r, B, rotation)[0], alone = normal_velocity(r, B, rotation);
      ASSERT_EQ(std::memcmp(&full, &alone, sizeof(double)), 0) << k << " " << full << " " << alone;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 40000);
}

TEST(SolverRows, TheJamDetectorNeedsUnconvergedGrowthByHalf) {
  EXPECT_TRUE(normal_impulses_grew(false, 1.0, 1.6));
  EXPECT_FALSE(normal_impulses_grew(false, 1.0, 1.4));  // slow, but settled
  EXPECT_FALSE(normal_impulses_grew(true, 1.0, 3.0));   // converged
  EXPECT_FALSE(normal_impulses_grew(false, -1.0, 3.0)); // never reached half the cap
  // An accelerated rigid solve: growth by half since the first sweep while the last
  // sweep still changed the impulses by a tenth of the first's change.
  EXPECT_TRUE(jam_persisted(5, 1.0, 0.5, 1.0, 1e6));
  EXPECT_FALSE(jam_persisted(5, 1.0, 0.05, 1.0, 1e6));   // the change fell: a cold start converging
  EXPECT_FALSE(jam_persisted(5, 1.0, 1.0, 1.0, 1.4));    // changing, but settled
  EXPECT_FALSE(jam_persisted(2, 1.0, 1.0, 1.0, 1e6));    // two sweeps: nothing extrapolated yet
  EXPECT_FALSE(jam_persisted(5, 1.0, 1.0, -1.0, 1e6));   // no first sweep recorded
  std::vector<SolverRow> rows(3);
  rows[0].lambda[0] = 1.0;
  rows[1].lambda[0] = 0.5;
  rows[2].lambda = Vec3(0.25, 9.0, 9.0);  // tangential parts do not count
  EXPECT_EQ(normal_impulse_sum(rows), 1.75);
}

}  // namespace
}  // namespace ratchet

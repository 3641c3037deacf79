// The exact local Coulomb solve: every returned impulse must satisfy the contact law
// it claims (Signorini + Coulomb) for the post-step velocity u = w + W lambda.
#include "ratchet/solver/local_coulomb.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "ratchet/core/random.hpp"

namespace ratchet {
namespace {

// A random symmetric positive definite 3x3 Delassus block, as H^T M^-1 H of a contact
// between two random rigid bodies would give (diagonally dominant but coupled).
Mat3 random_delassus(Rng& rng) {
  Mat3 A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A(i, j) = uniform(rng, -1.0, 1.0);
  return A * A.transpose() + 0.2 * Mat3::Identity();
}

TEST(LocalCoulomb, SeparatingContactGetsNoImpulse) {
  const Mat3 W = Mat3::Identity();
  const LocalSolution s = solve_local_coulomb(W, Vec3(0.3, 1.0, -2.0), 0.5);
  EXPECT_EQ(s.status, LocalStatus::Open);
  EXPECT_EQ(s.lambda, Vec3::Zero());
}

TEST(LocalCoulomb, SticksInsideTheCone) {
  // Isotropic W: the stick impulse is -w; |lambda_t| = 0.3 <= 0.5 * 1.
  const LocalSolution s = solve_local_coulomb(Mat3::Identity(), Vec3(-1.0, 0.3, 0.0), 0.5);
  EXPECT_EQ(s.status, LocalStatus::Stick);
  EXPECT_NEAR(s.lambda[0], 1.0, 1e-15);
  EXPECT_NEAR(s.lambda[1], -0.3, 1e-15);
}

TEST(LocalCoulomb, SlidesOnTheConeAgainstTheSlidingVelocity) {
  // Isotropic W, tangential drive 2 > mu * 1: lambda_n = 1, lambda_t = -mu along x,
  // u_t = 2 - 0.5 = 1.5 along x.
  const LocalSolution s = solve_local_coulomb(Mat3::Identity(), Vec3(-1.0, 2.0, 0.0), 0.5);
  EXPECT_EQ(s.status, LocalStatus::Slide);
  EXPECT_NEAR(s.lambda[0], 1.0, 1e-14);
  EXPECT_NEAR(s.lambda[1], -0.5, 1e-14);
  EXPECT_NEAR(s.lambda[2], 0.0, 1e-14);
}

TEST(LocalCoulomb, MuZeroEqualsTheNormalOnlySolveExactly) {
  Rng rng(3);
  for (int k = 0; k < 1000; ++k) {
    const Mat3 W = random_delassus(rng);
    const Vec3 w(uniform(rng, -2, 1), uniform(rng, -2, 2), uniform(rng, -2, 2));
    const LocalSolution s = solve_local_coulomb(W, w, 0.0);
    EXPECT_EQ(s.lambda[0], solve_local_normal(W(0, 0), w[0]));  // bit for bit
    EXPECT_EQ(s.lambda[1], 0.0);
    EXPECT_EQ(s.lambda[2], 0.0);
  }
}

// Property test over random coupled problems: the solution satisfies the law.
TEST(LocalCoulomb, RandomProblemsSatisfySignoriniAndCoulomb) {
  Rng rng(11);
  int counts[3] = {0, 0, 0};
  double worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const Mat3 W = random_delassus(rng);
    const Vec3 w(uniform(rng, -2, 1), uniform(rng, -3, 3), uniform(rng, -3, 3));
    const double mu = uniform(rng, 0.05, 1.0);
    const LocalSolution s = solve_local_coulomb(W, w, mu);
    const Vec3 u = w + W * s.lambda;
    const double scale = 1.0 + w.norm();
    ++counts[static_cast<int>(s.status)];
    SCOPED_TRACE(::testing::Message() << "problem " << k);
    // Tolerances: the slide direction is found to ~1e-13 and W has condition numbers up
    // to ~100, so 1e-9 relative is round-off with a wide margin.
    const double tol = 1e-9 * scale;
    EXPECT_GE(s.lambda[0], 0.0);
    EXPECT_GE(u[0], -tol);
    EXPECT_NEAR(s.lambda[0] * u[0], 0.0, tol * (1.0 + s.lambda[0]));
    const double lt = std::hypot(s.lambda[1], s.lambda[2]);
    EXPECT_LE(lt, mu * s.lambda[0] + tol);
    if (s.status == LocalStatus::Stick) {
      EXPECT_NEAR(std::hypot(u[1], u[2]), 0.0, tol);
    } else if (s.status == LocalStatus::Slide) {
      EXPECT_NEAR(lt, mu * s.lambda[0], tol);
      // lambda_t antiparallel to u_t.
      const double ut = std::hypot(u[1], u[2]);
      if (ut > 1e-6 && lt > 1e-6) {
        const double cosang = (u[1] * s.lambda[1] + u[2] * s.lambda[2]) / (ut * lt);
        worst = std::max(worst, 1.0 + cosang);
        EXPECT_NEAR(cosang, -1.0, 1e-9);
      }
    }
  }
  std::cout << "open " << counts[0] << ", stick " << counts[1] << ", slide " << counts[2]
            << ", worst 1 + cos(lambda_t, u_t) = " << worst << "\n";
  EXPECT_GT(counts[1], 500);  // the random set exercises every branch (834 stick here)
  EXPECT_GT(counts[2], 1000);
  EXPECT_GT(counts[0], 1000);
}

// Two slides solved together (the sweep's pairs) give each the bits it has alone, from
// hints near and far (Newton converging in few or many steps, or failing), so that one
// lane stops while the other goes on.
TEST(LocalCoulomb, SlidesSolvedInPairsHaveTheBitsOfEachAlone) {
  Rng rng(29);
  int pairs = 0, found_both = 0, one_failed = 0;
  for (int k = 0; k < 4000; ++k) {
    Mat3 W[2];
    Vec3 w[2], lambda_alone[2];
    double mu[2];
    Eigen::Vector2d hint[2];
    bool alone[2];
    for (int j = 0; j < 2; ++j) {
      W[j] = random_delassus(rng);
      w[j] = Vec3(uniform(rng, -2, -0.1), uniform(rng, -3, 3), uniform(rng, -3, 3));
      mu[j] = uniform(rng, 0.05, 1.0);
      // Near the slide's direction (the exact solve's), or anywhere.
      const Vec3 exact = solve_local_coulomb(W[j], w[j], mu[j]).lambda;
      const double spread = (k + j) % 3 == 0 ? 3.0 : 1e-3;
      Eigen::Vector2d h(exact[1] + spread * uniform(rng, -1, 1), exact[2] + spread * uniform(rng, -1, 1));
      hint[j] = h.norm() > 0.0 ? Eigen::Vector2d(h.normalized()) : Eigen::Vector2d(1.0, 0.0);
      alone[j] = detail::slide_from_hint(W[j], w[j], mu[j], hint[j], lambda_alone[j]);
    }
    const Mat3* Wp[2] = {&W[0], &W[1]};
    const Vec3* wp[2] = {&w[0], &w[1]};
    const Eigen::Vector2d* hp[2] = {&hint[0], &hint[1]};
    Vec3 lambda_pair[2] = {Vec3::Constant(-7.0), Vec3::Constant(-7.0)};
    Vec3* out[2] = {&lambda_pair[0], &lambda_pair[1]};
    bool found[2];
    detail::slide_from_hints(Wp, wp, mu, hp, out, found);
    for (int j = 0; j < 2; ++j) {
      ASSERT_EQ(found[j], alone[j]) << k << " lane " << j;
      if (found[j]) {
        ASSERT_EQ(std::memcmp(lambda_pair[j].data(), lambda_alone[j].data(), sizeof(Vec3)), 0) << k;
      }
    }
    ++pairs;
    found_both += found[0] && found[1];
    one_failed += found[0] != found[1];
  }
  EXPECT_EQ(pairs, 4000);
  EXPECT_GT(found_both, 1000);  // the lanes' iterations overlap in most pairs
  EXPECT_GT(one_failed, 50);    // and some pairs have one lane fail (the cold path's case)
}

// The warm start's clip is project_onto_cone's clip but for its rounding: the two agree
// to a few ulps of the impulse, and where the cap is zero the clip's tangent is +0.
TEST(LocalCoulomb, KeptImpulseIsClippedAsProjectOntoCone) {
  Rng rng(5);
  for (int k = 0; k < 10000; ++k) {
    const Vec3 l(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0));
    const double mu = uniform(rng, 0.0, 1.0);
    // 1e-15: hypot and sqrt of the sum of squares differ by an ulp or so, of |l| <= 2.
    EXPECT_LE((clip_kept_impulse(l, mu) - project_onto_cone(l, mu)).norm(), 1e-15) << l.transpose();
  }
  EXPECT_EQ(clip_kept_impulse(Vec3(1.0, 0.2, -0.1), 0.5), Vec3(1.0, 0.2, -0.1));  // inside: kept
  const Vec3 pulled = clip_kept_impulse(Vec3(-1.0, -0.3, -0.4), 0.5);
  EXPECT_EQ(pulled, Vec3::Zero());
  EXPECT_FALSE(std::signbit(pulled[1]) || std::signbit(pulled[2]));
}

// Anderson's write_extrapolated (solver/nsgs.cpp) writes an all-+0 extrapolation (an
// open row's) as it is, without the projection: exact only while the projection leaves
// +0 as +0.
TEST(LocalCoulomb, TheConeLeavesPositiveZeroAsItIs) {
  for (double mu : {0.0, 0.3, 1.0}) {
    const Vec3 p = project_onto_cone(Vec3(0.0, 0.0, 0.0), mu);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(p[j], 0.0) << mu;
      EXPECT_FALSE(std::signbit(p[j])) << mu << " entry " << j;
    }
  }
}

}  // namespace
}  // namespace ratchet

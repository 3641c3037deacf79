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
TEST(LocalCoulomb, SlidesSolvedTogetherHaveTheBitsOfEachAlone) {
  Rng rng(29);
  int batches = 0, found_all = 0, some_failed = 0;
  constexpr int L = detail::kSlideLanes;
  for (int k = 0; k < 4000; ++k) {
    const int n = 2 + k % (L - 1);  // 2, 3 and 4 lanes
    Mat3 W[L];
    Vec3 w[L], lambda_alone[L];
    double mu[L];
    Eigen::Vector2d hint[L];
    bool alone[L];
    for (int j = 0; j < n; ++j) {
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
    const Mat3* Wp[L];
    const Vec3* wp[L];
    const Eigen::Vector2d* hp[L];
    Vec3 lambda_batch[L];
    Vec3* out[L];
    for (int j = 0; j < n; ++j) {
      Wp[j] = &W[j];
      wp[j] = &w[j];
      hp[j] = &hint[j];
      lambda_batch[j] = Vec3::Constant(-7.0);
      out[j] = &lambda_batch[j];
    }
    bool found[L];
    detail::slide_from_hints(n, Wp, wp, mu, hp, out, found);
    int n_found = 0;
    for (int j = 0; j < n; ++j) {
      ASSERT_EQ(found[j], alone[j]) << k << " lane " << j << " of " << n;
      if (found[j]) {
        ASSERT_EQ(std::memcmp(lambda_batch[j].data(), lambda_alone[j].data(), sizeof(Vec3)), 0) << k;
        ++n_found;
      }
    }
    ++batches;
    found_all += n_found == n;
    some_failed += n_found > 0 && n_found < n;
  }
  EXPECT_EQ(batches, 4000);
  EXPECT_GT(found_all, 1000);    // the lanes' iterations overlap in most batches
  EXPECT_GT(some_failed, 50);    // and some batches have a lane fail (the cold path's case)
}

// The inexact slide (solver.slide_newton_steps): lanes with a step budget, mixed with
// exact ones, still have the bits each has alone with its own budget.
TEST(LocalCoulomb, SlidesWithAStepBudgetSolvedTogetherHaveTheBitsOfEachAlone) {
  Rng rng(31);
  constexpr int L = detail::kSlideLanes;
  int cut_found = 0;
  for (int k = 0; k < 2000; ++k) {
    const int n = 2 + k % (L - 1);
    Mat3 W[L];
    Vec3 w[L], lambda_alone[L], lambda_batch[L];
    double mu[L];
    Eigen::Vector2d hint[L];
    bool alone[L], found[L];
    int steps[L];
    const Mat3* Wp[L];
    const Vec3* wp[L];
    const Eigen::Vector2d* hp[L];
    Vec3* out[L];
    for (int j = 0; j < n; ++j) {
      W[j] = random_delassus(rng);
      w[j] = Vec3(uniform(rng, -2, -0.1), uniform(rng, -3, 3), uniform(rng, -3, 3));
      mu[j] = uniform(rng, 0.05, 1.0);
      const double a = uniform(rng, 0.0, 2.0 * M_PI);
      hint[j] = Eigen::Vector2d(std::cos(a), std::sin(a));
      steps[j] = (k + j) % 4;  // 0 (exact), 1, 2 or 3 steps
      alone[j] = detail::slide_from_hint(W[j], w[j], mu[j], hint[j], lambda_alone[j], steps[j]);
      Wp[j] = &W[j];
      wp[j] = &w[j];
      hp[j] = &hint[j];
      out[j] = &lambda_batch[j];
    }
    detail::slide_from_hints(n, Wp, wp, mu, hp, out, found, steps);
    for (int j = 0; j < n; ++j) {
      ASSERT_EQ(found[j], alone[j]) << k << " lane " << j;
      if (found[j]) ASSERT_EQ(std::memcmp(lambda_batch[j].data(), lambda_alone[j].data(), sizeof(Vec3)), 0) << k;
      cut_found += found[j] && steps[j] > 0;
    }
  }
  EXPECT_GT(cut_found, 1000);
}

// An inexact slide returns an impulse on the cone, against its own slide velocity, and
// repeated from its own answer (as the sweeps repeat it) it reaches the exact slide: its
// fixed point is the exact law's.
TEST(LocalCoulomb, AnInexactSlideIsOnTheConeAndItsRepetitionReachesTheExactSlide) {
  Rng rng(37);
  int checked = 0, far_starts = 0;
  for (int k = 0; k < 4000; ++k) {
    const Mat3 W = random_delassus(rng);
    const Vec3 w(uniform(rng, -2, -0.1), uniform(rng, -3, 3), uniform(rng, -3, 3));
    const double mu = uniform(rng, 0.05, 1.0);
    const LocalSolution exact = solve_local_coulomb(W, w, mu);
    Eigen::Vector2d d;
    if (exact.status != LocalStatus::Slide || !slide_direction(exact.lambda, mu, d)) continue;
    // A start 0.05-0.3 rad off the answer, as a sweep's changed neighbours leave it.
    const double off = (k % 2 ? 1.0 : -1.0) * uniform(rng, 0.05, 0.3);
    Eigen::Vector2d hint(d.x() * std::cos(off) - d.y() * std::sin(off), d.x() * std::sin(off) + d.y() * std::cos(off));
    Vec3 lambda;
    bool ok = detail::slide_from_hint(W, w, mu, hint, lambda, 1);
    if (!ok) continue;  // the sweep then solves it exactly (the cold way)
    ++far_starts;
    const double lt = std::sqrt(lambda[1] * lambda[1] + lambda[2] * lambda[2]);
    ASSERT_GE(lambda[0], 0.0) << k;
    ASSERT_NEAR(lt, mu * lambda[0], 1e-12 * (1.0 + lambda[0])) << k;  // on the cone to round-off
    const Vec3 u = w + W * lambda;
    ASSERT_LT(u[1] * lambda[1] + u[2] * lambda[2], 0.0) << k;  // friction against the slide velocity
    for (int it = 0; it < 12 && ok; ++it) {
      ok = slide_direction(lambda, mu, hint) && detail::slide_from_hint(W, w, mu, hint, lambda, 1);
    }
    ASSERT_TRUE(ok) << k;
    // Newton converges quadratically: twelve repetitions reach the exact solve to round-off
    // (1e-10 of the impulse: W's conditioning, 0.2 at least on its diagonal, with margin).
    ASSERT_LT((lambda - exact.lambda).norm(), 1e-10 * (1.0 + exact.lambda.norm())) << k;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_EQ(checked, far_starts);
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


// The cold slide taken apart as a coloured sweep takes it (nsgs.cpp, SlideBatch): the fixed
// point when the row is put off, Newton from the stick direction among other rows' lanes,
// and the scan for a lane that ends at no admissible slide; each with slide_cold's bits.
TEST(LocalCoulomb, AColdSlideInStagesHasTheBitsOfSlideCold) {
  Rng rng(31);
  constexpr int L = detail::kSlideLanes;
  int slides = 0, by_fixed_point = 0, by_newton = 0, by_scan = 0;
  for (int k = 0; k < 20000 && slides < 4000;) {
    Mat3 W[L];
    Vec3 w[L], stick[L], whole[L];
    double mu[L], lt[L];
    int n = 0;
    while (n < L && k < 20000) {
      ++k;
      // Every fourth an isotropic block (a sphere on a plane: the fixed point's case), the
      // others coupled, with friction up to 3 so that Newton from the stick direction
      // sometimes ends at no admissible slide (the scan's case).
      W[n] = k % 4 == 0 ? Mat3(uniform(rng, 0.5, 2.0) * Mat3::Identity()) : random_delassus(rng);
      w[n] = Vec3(uniform(rng, -2, -0.1), uniform(rng, -3, 3), uniform(rng, -3, 3));
      mu[n] = uniform(rng, 0.05, 3.0);
      LocalSolution sol;
      if (solve_local_before_slide(W[n], W[n].inverse(), w[n], mu[n], 0.0, sol, stick[n], lt[n])) continue;
      whole[n] = detail::slide_cold(W[n], w[n], mu[n], stick[n], lt[n]).lambda;
      ++n;
    }
    Eigen::Vector2d d0[L];
    Vec3 staged[L];
    const Mat3* Wp[L];
    const Vec3* wp[L];
    const Eigen::Vector2d* hp[L];
    Vec3* out[L];
    double mu_lane[L];
    int lane_of[L], lanes = 0;
    for (int j = 0; j < n; ++j) {
      if (detail::slide_fixed_point(W[j], w[j], mu[j], stick[j], lt[j], d0[j], staged[j])) {
        ++by_fixed_point;
        continue;
      }
      Wp[lanes] = &W[j];
      wp[lanes] = &w[j];
      hp[lanes] = &d0[j];
      out[lanes] = &staged[j];
      mu_lane[lanes] = mu[j];
      lane_of[lanes++] = j;
    }
    bool found[L] = {};
    if (lanes >= 2) detail::slide_from_hints(lanes, Wp, wp, mu_lane, hp, out, found);
    if (lanes == 1) found[0] = detail::slide_from_hint(*Wp[0], *wp[0], mu_lane[0], *hp[0], *out[0]);
    for (int a = 0; a < lanes; ++a) {
      const int j = lane_of[a];
      if (found[a]) {
        ++by_newton;
      } else {
        staged[j] = detail::slide_scan(W[j], w[j], mu[j], stick[j], d0[j]);
        ++by_scan;
      }
    }
    for (int j = 0; j < n; ++j) {
      ASSERT_EQ(std::memcmp(staged[j].data(), whole[j].data(), sizeof(Vec3)), 0) << "problem " << k << " lane " << j;
      ++slides;
    }
  }
  EXPECT_GE(slides, 4000);
  EXPECT_GT(by_newton, 1000);  // most cold slides end in Newton's lanes
  EXPECT_GT(by_fixed_point, 100);  // the isotropic blocks end in the fixed point
  EXPECT_GT(by_scan, 0);           // and the scan is reached through a lane
  std::cout << "fixed point " << by_fixed_point << ", Newton " << by_newton << ", scan " << by_scan << "\n";
}

}  // namespace
}  // namespace ratchet

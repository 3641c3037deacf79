// Tests of contact/manifold_reuse: the motion bound covers every vertex's actual motion,
// a manifold replayed at the pose it was built at is the manifold, and a replayed
// manifold's deepest gap stays within 2 delta of a fresh build's after motions of size
// delta (the bound stated in manifold_reuse.hpp), for every pose category.
#include "ratchet/contact/manifold_reuse.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ratchet/core/random.hpp"
#include "random_pairs.hpp"

namespace ratchet {
namespace {

using namespace test;

double deepest(const ContactManifold& m) {
  double g = HUGE_VAL;
  for (int c = 0; c < m.count; ++c) g = std::min(g, m.points[static_cast<std::size_t>(c)].gap);
  return g;
}

// Every vertex of A and B, in A's frame, moves by at most pair_motion between two poses.
TEST(ManifoldReuse, TheMotionBoundCoversEveryVertex) {
  Rng rng(3);
  double tightest = 0.0;
  for (int k = 0; k < 2000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    generate_pose(static_cast<Category>(k % kCategories), rng, A, B);
    const PairPose before = pair_pose(A.view(), B.view());
    auto in_a = [&](const Posed& p, int i) { return Vec3(A.R().transpose() * (p.vertex(i) - A.center())); };
    std::vector<Vec3> va, vb;
    for (int i = 0; i < static_cast<int>(A.shape().vertices.size()); ++i) va.push_back(in_a(A, i));
    for (int i = 0; i < static_cast<int>(B.shape().vertices.size()); ++i) vb.push_back(in_a(B, i));
    const double size = std::pow(10.0, uniform(rng, -6.0, -2.0));
    perturb(A, rng, size, size, A.view().scale * (1.0 + uniform(rng, -1e-3, 1e-3)));
    perturb(B, rng, size, size, B.view().scale * (1.0 + uniform(rng, -1e-3, 1e-3)));
    const double bound =
        pair_motion(before, pair_pose(A.view(), B.view()), A.shape().bounding_radius, B.shape().bounding_radius);
    double moved = 0.0;
    for (int i = 0; i < static_cast<int>(va.size()); ++i) moved = std::max(moved, (in_a(A, i) - va[static_cast<std::size_t>(i)]).norm());
    for (int i = 0; i < static_cast<int>(vb.size()); ++i) moved = std::max(moved, (in_a(B, i) - vb[static_cast<std::size_t>(i)]).norm());
    ASSERT_LE(moved, bound * (1.0 + 1e-9) + 1e-15) << "pair " << k;
    tightest = std::max(tightest, moved / bound);
  }
  // Not a loose bound: some pair's vertex moves by a good part of it.
  EXPECT_GT(tightest, 0.3);
}

TEST(ManifoldReuse, ReplayedAtItsOwnPoseTheManifoldIsUnchanged) {
  Rng rng(5);
  int compared = 0;
  for (int k = 0; k < 1000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    generate_pose(static_cast<Category>(k % kCategories), rng, A, B);
    CommonPlaneCache cache;
    ContactManifold m;
    CommonPlaneResult plane;
    collide_polyhedra(A.view(), B.view(), 0.05, cache, m, &plane);
    const KeptManifold kept = keep_manifold(0, 1, A.view(), B.view(), m, plane.gap, plane.feature == PlaneFeature::FaceB);
    ContactManifold again;
    replay_manifold(kept, A.view(), B.view(), again);
    ASSERT_EQ(again.count, m.count);
    for (int c = 0; c < m.count; ++c) {
      const ContactPoint &x = m.points[static_cast<std::size_t>(c)], &y = again.points[static_cast<std::size_t>(c)];
      const double L = A.radius() + B.radius();
      EXPECT_NEAR(x.gap, y.gap, 1e-12 * L) << "pair " << k;
      EXPECT_LE((x.point - y.point).norm(), 1e-12 * L) << "pair " << k;
      EXPECT_LE((x.normal - y.normal).norm(), 1e-12) << "pair " << k;
      EXPECT_EQ(x.feature_a, y.feature_a);
      EXPECT_EQ(x.feature_b, y.feature_b);
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

// Pairs in contact, moved step by step as bodies of a bed (random small motions and
// thermal growth) while their accumulated motion stays below delta: the replayed
// manifold's deepest gap against a fresh build's at the same pose. A pair found apart
// beyond margin + motion stays apart.
TEST(ManifoldReuse, ReplayedGapsStayWithinTwiceTheBound) {
  constexpr double kMargin = 0.05;
  Rng rng(7);
  long replays = 0, empties = 0;
  double worst = 0.0;
  for (int k = 0; k < 3000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    const Category cat = static_cast<Category>(k % kCategories);
    generate_pose(cat, rng, A, B);
    const double delta = std::pow(10.0, uniform(rng, -4.0, -2.0));
    CommonPlaneCache cache;
    ContactManifold m;
    CommonPlaneResult plane;
    collide_polyhedra(A.view(), B.view(), kMargin, cache, m, &plane);
    const KeptManifold kept = keep_manifold(0, 1, A.view(), B.view(), m, plane.gap, plane.feature == PlaneFeature::FaceB);
    for (int step = 0; step < 30; ++step) {
      const double size = delta * std::pow(10.0, uniform(rng, -3.0, -1.0));
      nudge(uniform01(rng) < 0.5 ? A : B, rng, size, uniform01(rng) < 0.3 ? 1e-6 : 0.0);
      const double moved =
          pair_motion(kept.pose, pair_pose(A.view(), B.view()), A.shape().bounding_radius, B.shape().bounding_radius);
      if (moved > delta) break;  // the engine would build anew here
      ContactManifold replayed, fresh;
      replay_manifold(kept, A.view(), B.view(), replayed);
      CommonPlaneCache scratch_cache = cache;
      collide_polyhedra(A.view(), B.view(), kMargin, scratch_cache, fresh);
      if (kept.count == 0) {
        if (kept.gap_bound - moved > kMargin) {
          EXPECT_EQ(fresh.count, 0) << "pair " << k << ": an empty pair came into reach";
          ++empties;
        }
        continue;
      }
      const double g_fresh = fresh.count > 0 ? deepest(fresh) : kMargin;
      const double error = std::abs(deepest(replayed) - g_fresh);
      EXPECT_LE(error, 2.0 * delta) << "pair " << k << " (" << kCategoryName[cat] << ") step " << step;
      worst = std::max(worst, error / delta);
      ++replays;
    }
  }
  EXPECT_GT(replays, 10000);
  EXPECT_GT(empties, 100);
  // The replay does move: its gaps are not simply the fresh ones.
  EXPECT_GT(worst, 1e-6);
}

}  // namespace
}  // namespace ratchet

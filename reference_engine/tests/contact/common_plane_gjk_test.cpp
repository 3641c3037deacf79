// Tests of contact/common_plane_gjk: GJK's distance and its polished normal, on boxes
// where both are known in closed form and on random pairs against the brute-force
// oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>

#include "ratchet/contact/common_plane_detail.hpp"
#include "ratchet/core/random.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"
#include "random_pairs.hpp"
#include "sat_oracle.hpp"

namespace ratchet {
namespace {

using namespace test;

// Distance agreement with the oracle: both scan the same world vertices (coordinates up
// to ~16), GJK stops at 1e-14 relative; 1e-9 is far above either rounding.
constexpr double kGapTol = 1e-9;
// Pairs closer than this are left to the SAT by the engine (GJK's direction is then
// dominated by rounding); GJK must prove every pair farther apart.
constexpr double kConditionedGap = 1e-7;

// The one-pair simplex GJK starts from: the supports of A and B along the line of centres.
cp_detail::Simplex start_simplex(const PolyhedronView& a, const PolyhedronView& b) {
  const cp_detail::AxisValue av = cp_detail::evaluate_axis(a, b, (a.center - b.center).normalized());
  cp_detail::Simplex s;
  s.n = 1;
  s.v[0].ia = av.ia;
  s.v[0].ib = av.ib;
  s.v[0].w = a.world_vertices[av.ia] - b.world_vertices[av.ib];
  return s;
}

// Face over face 0.25 apart, offset sideways: the distance is 0.25 and the closest
// features are two faces, whose exact normal the polish recovers from GJK's direction.
TEST(CommonPlaneGjk, FaceOverFaceGivesTheDistanceAndTheExactNormal) {
  const PolyhedronBuild box = build_box(Vec3(0.5, 0.5, 0.5));
  Posed A(box.shape), B(box.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  A.place(Vec3(0.3, 0.2, 1.25), Mat3::Identity());
  const cp_detail::GjkOutcome go = cp_detail::gjk(A.view(), B.view(), start_simplex(A.view(), B.view()), HUGE_VAL);
  ASSERT_TRUE(go.proven_apart);
  EXPECT_FALSE(go.early_out);
  // s is a lower bound that GJK raises to 1e-14 relative of |v|.
  EXPECT_LE(go.s, 0.25 + 1e-15);
  EXPECT_GE(go.s, 0.25 - 1e-13);
  Vec3 polished;
  ASSERT_TRUE(cp_detail::polish_normal(A.view(), B.view(), go.simplex, go.v.normalized(), polished));
  // The faces' edges have exact zero z components, so the polished normal is +z to
  // rounding of the projections (~1e-16).
  EXPECT_LT(angle_between(polished, Vec3::UnitZ()), 1e-14);
}

// Random pairs: every pair apart by more than kConditionedGap is proven apart at the
// oracle's distance; no overlapping pair is; a cutoff below the distance stops early
// with a value above it that is still a lower bound.
TEST(CommonPlaneGjk, AgreesWithTheOracleOnRandomPairs) {
  Rng rng(17);
  const Category cats[] = {kRandom, kNearTouch, kFaceFace, kVertexVertex};
  int apart = 0, overlapping = 0, early = 0;
  for (int k = 0; k < 4000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    generate_pose(cats[k % 4], rng, A, B);
    const OracleResult o = oracle_common_plane(A.view(), B.view());
    const cp_detail::Simplex s0 = start_simplex(A.view(), B.view());
    const cp_detail::GjkOutcome go = cp_detail::gjk(A.view(), B.view(), s0, HUGE_VAL);
    if (o.gap > kConditionedGap) {
      ++apart;
      EXPECT_TRUE(go.proven_apart) << "pair " << k << " gap " << o.gap;
      EXPECT_NEAR(go.s, o.gap, kGapTol) << "pair " << k;
      const double cutoff = 0.5 * o.gap;
      const cp_detail::GjkOutcome cut = cp_detail::gjk(A.view(), B.view(), s0, cutoff);
      early += cut.early_out;
      EXPECT_TRUE(cut.early_out && cut.s > cutoff && cut.s <= o.gap + kGapTol) << "pair " << k;
      EXPECT_LE(cut.iterations, go.iterations);
    } else if (o.gap < -kGapTol) {
      ++overlapping;
      EXPECT_FALSE(go.proven_apart) << "pair " << k << " gap " << o.gap;
    }
  }
  // Both sides must be exercised, or this test shows nothing.
  EXPECT_GT(apart, 1000);
  EXPECT_GT(overlapping, 1000);
  EXPECT_EQ(early, apart);
}

}  // namespace
}  // namespace ratchet

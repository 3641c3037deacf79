// Tests of contact/common_plane_search: the pruned facet search must find what a search
// of every facet with the same arithmetic finds, bit for bit, while evaluating far fewer
// axes from a warm start.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <numeric>
#include <vector>

#include "ratchet/contact/common_plane_detail.hpp"
#include "ratchet/core/random.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"
#include "random_pairs.hpp"

namespace ratchet {
namespace {

using namespace test;

// Every facet of D: all face axes of both bodies and all edge pairs whose arcs cross,
// evaluated by the engine's own helpers; the largest value.
double best_facet_unpruned(const PolyhedronView& a, const PolyhedronView& b, int& axes) {
  double top = -HUGE_VAL;
  Vec3 n;
  axes = 0;
  for (int f = 0; f < static_cast<int>(a.shape->faces.size()); ++f, ++axes)
    top = std::max(top, cp_detail::face_a_value(a, b, f, n));
  for (int g = 0; g < static_cast<int>(b.shape->faces.size()); ++g, ++axes)
    top = std::max(top, cp_detail::face_b_value(a, b, g, n));
  for (int i = 0; i < static_cast<int>(a.shape->edges.size()); ++i)
    for (int j = 0; j < static_cast<int>(b.shape->edges.size()); ++j) {
      double s = 0.0;
      if (cp_detail::edge_pair_facet(cp_detail::edge_data(a, i), cp_detail::edge_data(b, j), s, n)) {
        top = std::max(top, s);
        ++axes;
      }
    }
  return top;
}

// Cold (line of centres) and warm (the cold result as a facet start) searches on random
// pairs of every category. Pruning is rigorous, so both end at the largest of the start
// value and every facet's value, the same bits; pruning must skip most axes.
TEST(CommonPlaneSearch, PrunedSearchFindsTheBestFacetBitForBit) {
  Rng rng(23);
  long cold_axes = 0, warm_axes = 0, all_axes = 0, pairs = 0, facet_won = 0;
  for (int k = 0; k < 3000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    generate_pose(static_cast<Category>(k % kCategories), rng, A, B);
    const PolyhedronView &a = A.view(), &b = B.view();
    cp_detail::Candidate best, best_face;
    best.n = (a.center - b.center).normalized();
    best.s = cp_detail::evaluate_axis(a, b, best.n).s;
    best.kind = PlaneFeature::Axis;
    const double start = best.s;
    CommonPlaneResult r;
    cp_detail::sat_search(a, b, best, best_face, HUGE_VAL, r);
    int axes = 0;
    const double expected = std::max(start, best_facet_unpruned(a, b, axes));
    EXPECT_TRUE(same_bits(best.s, expected)) << "pair " << k << ": " << best.s << " vs " << expected;
    facet_won += best.kind != PlaneFeature::Axis;

    cp_detail::Candidate warm = best, warm_face;
    if (warm.kind == PlaneFeature::FaceA || warm.kind == PlaneFeature::FaceB) warm_face = warm;
    CommonPlaneResult rw;
    cp_detail::sat_search(a, b, warm, warm_face, HUGE_VAL, rw);
    EXPECT_TRUE(same_bits(warm.s, best.s)) << "pair " << k;
    ++pairs;
    cold_axes += r.sat_axes;
    warm_axes += rw.sat_axes;
    all_axes += axes;
  }
  const double cold = static_cast<double>(cold_axes) / static_cast<double>(pairs);
  const double warm = static_cast<double>(warm_axes) / static_cast<double>(pairs);
  const double all = static_cast<double>(all_axes) / static_cast<double>(pairs);
  std::cout << "axes evaluated per pair: unpruned " << all << ", cold " << cold << ", warm " << warm << "\n";
  EXPECT_GT(facet_won, pairs / 2);  // the start axis rarely wins: the search does the work
  // Measured: ~120 axes unpruned, ~9 cold, ~5 warm. Asserted: pruning drops three in
  // four axes, and the warm start needs fewer still.
  EXPECT_LT(cold, 0.25 * all);
  EXPECT_LT(warm, cold);
}

// top_supports: the kRefVertices highest vertices along u, highest first, lowest index
// on ties (a box's top face: its four corners in index order).
TEST(CommonPlaneSearch, TopSupportsAreTheHighestVerticesInOrder) {
  const PolyhedronBuild box = build_box(Vec3(0.5, 0.5, 0.5));
  Posed B(box.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  std::array<int, cp_detail::kRefVertices> idx{};
  ASSERT_EQ(cp_detail::top_supports(B.view(), Vec3::UnitZ(), idx), 4);
  EXPECT_EQ(idx, (std::array<int, 4>{4, 5, 6, 7}));

  Rng rng(29);
  for (int k = 0; k < 200; ++k) {
    int family = 0;
    Posed P(pick_shape(rng, family));
    P.place(Vec3::Zero(), random_rotation(rng));
    const Vec3 u = uniform_unit_vector(rng);
    std::vector<int> order(P.shape().vertices.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return u.dot(P.vertex(i)) > u.dot(P.vertex(j)); });
    ASSERT_EQ(cp_detail::top_supports(P.view(), u, idx), 4);
    for (int j = 0; j < 4; ++j) EXPECT_EQ(idx[static_cast<std::size_t>(j)], order[static_cast<std::size_t>(j)]) << k;
  }
}

}  // namespace
}  // namespace ratchet

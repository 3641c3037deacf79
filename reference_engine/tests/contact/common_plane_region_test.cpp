// Tests of contact/common_plane_region: manifolds on boxes, where the contact region is
// known in closed form (one test per region case), and on random contacts, where every
// point must be consistent with the plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <utility>
#include <vector>

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/common_plane_detail.hpp"
#include "ratchet/core/random.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"
#include "random_pairs.hpp"

namespace ratchet {
namespace {

using namespace test;

// Exact values up to rounding of coordinates of size ~1: 1e-12.
constexpr double kExact = 1e-12;

struct Boxes {
  PolyhedronBuild a, b;
  Boxes(const Vec3& ha, const Vec3& hb) : a(build_box(ha)), b(build_box(hb)) {}
};

std::vector<std::pair<std::int32_t, std::int32_t>> feature_pairs(const ContactManifold& m) {
  std::vector<std::pair<std::int32_t, std::int32_t>> f;
  for (int i = 0; i < m.count; ++i) f.emplace_back(m.points[static_cast<std::size_t>(i)].feature_a, m.points[static_cast<std::size_t>(i)].feature_b);
  std::sort(f.begin(), f.end());
  return f;
}

// Runs collide, checks normal +z and that every expected point is matched once.
void expect_manifold(const Posed& A, const Posed& B, const std::vector<Vec3>& expected, double gap,
                     ContactManifold& m) {
  CommonPlaneCache cache;
  ASSERT_TRUE(collide_polyhedra(A.view(), B.view(), 0.01, cache, m));
  ASSERT_EQ(m.count, static_cast<int>(expected.size()));
  std::vector<bool> used(expected.size(), false);
  for (int i = 0; i < m.count; ++i) {
    const ContactPoint& c = m.points[static_cast<std::size_t>(i)];
    EXPECT_LT(angle_between(c.normal, Vec3::UnitZ()), kExact);
    EXPECT_NEAR(c.gap, gap, kExact);
    bool found = false;
    for (std::size_t e = 0; e < expected.size() && !found; ++e)
      if (!used[e] && (c.point - expected[e]).norm() < kExact) used[e] = found = true;
    EXPECT_TRUE(found) << "unexpected contact point " << c.point.transpose();
  }
}

TEST(CommonPlaneManifold, BoxRestingOnBoxGivesTheFourCornersOfTheOverlap) {
  const Boxes boxes(Vec3(0.8, 1.5, 0.5), Vec3(1.0, 1.0, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  A.place(Vec3(0.5, 0.2, 0.99), Mat3::Identity());  // 0.01 into B's top face z = 0.5
  // Overlap rectangle: x in [-0.3, 1], y in [-1, 1]; points midway, z = 0.495.
  const std::vector<Vec3> corners = {Vec3(-0.3, -1, 0.495), Vec3(1, -1, 0.495), Vec3(1, 1, 0.495),
                                     Vec3(-0.3, 1, 0.495)};
  ContactManifold m;
  expect_manifold(A, B, corners, -0.01, m);

  // Feature ids survive a tiny perturbation.
  Rng rng(3);
  nudge(A, rng, 1e-7);
  ContactManifold m2;
  CommonPlaneCache cache;
  ASSERT_TRUE(collide_polyhedra(A.view(), B.view(), 0.01, cache, m2));
  EXPECT_EQ(feature_pairs(m), feature_pairs(m2));
}

TEST(CommonPlaneManifold, ScaledBoxOnBoxUsesTheScaledCorners) {
  // A unit cube at thermal scale 1.2 (half extent 0.6) resting 0.01 deep on B's top face.
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(1.0, 1.0, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  A.place(Vec3(0.2, 0.1, 0.5 + 0.6 - 0.01), Mat3::Identity(), 1.2);
  const std::vector<Vec3> corners = {Vec3(-0.4, -0.5, 0.495), Vec3(0.8, -0.5, 0.495), Vec3(0.8, 0.7, 0.495),
                                     Vec3(-0.4, 0.7, 0.495)};
  ContactManifold m;
  expect_manifold(A, B, corners, -0.01, m);
}

TEST(CommonPlaneManifold, EdgeOnFaceGivesTwoPoints) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(2.0, 2.0, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  // Rotated 45 deg about x: the lowest feature is an edge along x at depth 0.5 sqrt(2).
  const Mat3 R = Eigen::AngleAxisd(M_PI / 4.0, Vec3::UnitX()).toRotationMatrix();
  A.place(Vec3(0.1, 0.2, 0.5 + 0.5 * std::sqrt(2.0) - 0.001), R);
  ContactManifold m;
  expect_manifold(A, B, {Vec3(-0.4, 0.2, 0.4995), Vec3(0.6, 0.2, 0.4995)}, -0.001, m);
  for (int i = 0; i < m.count; ++i)
    EXPECT_EQ(m.points[static_cast<std::size_t>(i)].feature_b >> 24, static_cast<int>(FeatureKind::Face));

  Rng rng(4);
  nudge(A, rng, 1e-7);
  ContactManifold m2;
  CommonPlaneCache cache;
  ASSERT_TRUE(collide_polyhedra(A.view(), B.view(), 0.01, cache, m2));
  EXPECT_EQ(feature_pairs(m), feature_pairs(m2));
}

TEST(CommonPlaneManifold, VertexOnFaceGivesOnePoint) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(2.0, 2.0, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  // Corner (+,+,+) (build_box index 7) turned to point straight down.
  const Mat3 R = Quat::FromTwoVectors(Vec3(1, 1, 1).normalized(), -Vec3::UnitZ()).toRotationMatrix();
  A.place(Vec3(0.1, 0.2, 0.5 + 0.5 * std::sqrt(3.0) - 0.001), R);
  ContactManifold m;
  expect_manifold(A, B, {Vec3(0.1, 0.2, 0.4995)}, -0.001, m);
  EXPECT_EQ(m.points[0].feature_a, feature_id(FeatureKind::Vertex, 7));
  EXPECT_EQ(m.points[0].feature_b >> 24, static_cast<int>(FeatureKind::Face));

  Rng rng(5);
  nudge(A, rng, 1e-7);
  ContactManifold m2;
  CommonPlaneCache cache;
  ASSERT_TRUE(collide_polyhedra(A.view(), B.view(), 0.01, cache, m2));
  EXPECT_EQ(feature_pairs(m), feature_pairs(m2));
}

TEST(CommonPlaneManifold, CrossedEdgesGiveOnePoint) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  // B's top edge runs along y, A's bottom edge along x; they cross above the origin.
  const Mat3 Rb = Eigen::AngleAxisd(M_PI / 4.0, Vec3::UnitY()).toRotationMatrix();
  const Mat3 Ra = Eigen::AngleAxisd(M_PI / 4.0, Vec3::UnitX()).toRotationMatrix();
  const double h = 0.5 * std::sqrt(2.0);
  B.place(Vec3::Zero(), Rb);
  A.place(Vec3(0.0, 0.0, 2.0 * h + 0.002), Ra);  // 0.002 apart
  ContactManifold m;
  expect_manifold(A, B, {Vec3(0.0, 0.0, h + 0.001)}, 0.002, m);
  EXPECT_EQ(m.points[0].feature_a >> 24, static_cast<int>(FeatureKind::Edge));
  EXPECT_EQ(m.points[0].feature_b >> 24, static_cast<int>(FeatureKind::Edge));
}

TEST(CommonPlaneManifold, NoContactBeyondMargin) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  B.place(Vec3::Zero(), Mat3::Identity());
  A.place(Vec3(0.2, 0.1, 1.1), Mat3::Identity());  // face on face, 0.1 apart
  CommonPlaneCache cache;
  ContactManifold m;
  CommonPlaneResult plane;
  EXPECT_FALSE(collide_polyhedra(A.view(), B.view(), 0.05, cache, m, &plane));
  EXPECT_EQ(m.count, 0);
  EXPECT_GT(plane.gap, 0.05);
  // Within the margin: the four corners of the 0.8 x 0.9 overlap, gap 0.1 each.
  EXPECT_TRUE(collide_polyhedra(A.view(), B.view(), 0.2, cache, m, &plane));
  EXPECT_EQ(m.count, 4);
  EXPECT_NEAR(plane.gap, 0.1, kExact);
  for (int i = 0; i < m.count; ++i) EXPECT_NEAR(m.points[static_cast<std::size_t>(i)].gap, 0.1, kExact);
}

// On random touching pairs every manifold point lies in the band around the plane and
// its gap is the true distance between the surfaces there (never below the pair's gap).
TEST(CommonPlaneManifold, RandomContactsAreConsistentWithThePlane) {
  Rng rng(9);
  int counts[5] = {0, 0, 0, 0, 0};
  for (int k = 0; k < 3000; ++k) {
    int fa = 0, fb = 0;
    Posed A(pick_shape(rng, fa)), B(pick_shape(rng, fb));
    generate_pose(static_cast<Category>(kNearTouch + k % 5), rng, A, B);
    CommonPlaneCache cache;
    ContactManifold m;
    CommonPlaneResult plane;
    const bool touching = collide_polyhedra(A.view(), B.view(), 0.01, cache, m, &plane);
    ASSERT_EQ(touching, plane.gap <= 0.01);
    if (!touching) continue;
    ASSERT_GE(m.count, 1);
    ++counts[m.count];
    // Band 1e-3 r (r >= 0.5 * 0.2 for the thinnest axis is irrelevant: the band uses the
    // bounding radius, <= 1): no point deeper than the plane's gap allows, none farther
    // than the gap plus twice the band.
    for (int i = 0; i < m.count; ++i) {
      const ContactPoint& c = m.points[static_cast<std::size_t>(i)];
      EXPECT_GE(c.gap, plane.gap - 1e-9);
      EXPECT_LE(c.gap, plane.gap + 2e-3 + 1e-9);
      EXPECT_EQ(c.normal, plane.normal);
    }
  }
  std::cout << "\nManifold sizes on random contacts: 1:" << counts[1] << " 2:" << counts[2] << " 3:" << counts[3]
            << " 4:" << counts[4] << "\n";
  EXPECT_GT(counts[1], 0);
  EXPECT_GT(counts[2], 0);
  EXPECT_GT(counts[4], 0);
}

// build_manifold directly, with the plane given: two boxes turned 45 degrees about x
// touch along parallel edges (the edge-on-edge case with parallel segments); the
// region is the overlap of the edges, x in [0.1, 0.5], one end a vertex of each body.
TEST(CommonPlaneManifold, ParallelEdgesGiveTheEndsOfTheirOverlap) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  const Mat3 R = Eigen::AngleAxisd(M_PI / 4.0, Vec3::UnitX()).toRotationMatrix();
  const double h = 0.5 * std::sqrt(2.0);
  B.place(Vec3::Zero(), R);
  A.place(Vec3(0.6, 0.0, 2.0 * h - 0.001), R);  // 0.001 deep
  ContactManifold m;
  cp_detail::build_manifold(A.view(), B.view(), Vec3::UnitZ(), m);
  ASSERT_EQ(m.count, 2);
  const Vec3 expected[2] = {Vec3(0.1, 0.0, h - 0.0005), Vec3(0.5, 0.0, h - 0.0005)};
  int vertex_a = 0, vertex_b = 0;
  for (int i = 0; i < 2; ++i) {
    const ContactPoint& c = m.points[static_cast<std::size_t>(i)];
    EXPECT_NEAR(c.gap, -0.001, kExact);
    const bool at_lo = (c.point - expected[0]).norm() < kExact, at_hi = (c.point - expected[1]).norm() < kExact;
    EXPECT_TRUE(at_lo || at_hi) << "unexpected contact point " << c.point.transpose();
    // x = 0.1 is the end of A's edge, x = 0.5 the end of B's.
    if (at_lo) vertex_a += (c.feature_a >> 24) == static_cast<int>(FeatureKind::Vertex);
    if (at_hi) vertex_b += (c.feature_b >> 24) == static_cast<int>(FeatureKind::Vertex);
  }
  EXPECT_EQ(vertex_a, 1);
  EXPECT_EQ(vertex_b, 1);
}

// build_manifold directly: two cube corners tip to tip, 0.01 apart laterally (the
// vertex-on-vertex case): one point midway between them, with both vertex ids.
TEST(CommonPlaneManifold, VertexOnVertexGivesOnePointMidway) {
  const Boxes boxes(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5));
  Posed A(boxes.a.shape), B(boxes.b.shape);
  const Vec3 diagonal = Vec3(1, 1, 1).normalized();
  const double h = 0.5 * std::sqrt(3.0);
  B.place(Vec3::Zero(), Quat::FromTwoVectors(diagonal, Vec3::UnitZ()).toRotationMatrix());  // corner 7 up
  A.place(Vec3(0.01, 0.0, 2.0 * h + 0.002), Quat::FromTwoVectors(diagonal, -Vec3::UnitZ()).toRotationMatrix());
  ContactManifold m;
  cp_detail::build_manifold(A.view(), B.view(), Vec3::UnitZ(), m);
  ASSERT_EQ(m.count, 1);
  const ContactPoint& c = m.points[0];
  // FromTwoVectors puts the corners on the axis to ~1e-16: compare to 1e-12.
  EXPECT_NEAR(c.gap, 0.002, kExact);
  EXPECT_LT((c.point - Vec3(0.005, 0.0, h + 0.001)).norm(), kExact);
  EXPECT_EQ(c.feature_a, feature_id(FeatureKind::Vertex, 7));
  EXPECT_EQ(c.feature_b, feature_id(FeatureKind::Vertex, 7));
}

}  // namespace
}  // namespace ratchet

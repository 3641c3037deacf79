// The collision dispatch table: each (kind, kind) pair reaches its narrow-phase function
// with the pair's convention (normal from B to A), and walls reach theirs by kind.
#include "ratchet/contact/collide.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "ratchet/contact/narrow_phase.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"

namespace ratchet {
namespace {

struct Box {
  PolyhedronBuild build = build_box(Vec3(0.5, 0.5, 0.5));
  std::vector<Vec3> world;
  CollisionBody body;
  explicit Box(const Vec3& c) {
    for (const Vec3& v : build.shape.vertices) world.push_back(c + v);
    body.kind = ShapeKind::Polyhedron;
    body.center = c;
    body.poly.shape = &build.shape;
    body.poly.world_vertices = world.data();
    body.poly.center = c;
  }
};

CollisionBody sphere(const Vec3& c, double r) {
  CollisionBody b;
  b.kind = ShapeKind::Sphere;
  b.center = c;
  b.radius = r;
  return b;
}

TEST(Collide, SpherePairGoesToTheSphereFormula) {
  ContactManifold m, direct;
  CommonPlaneCache cache;
  collide_pair(sphere(Vec3(0, 0, 1.9), 1.0), sphere(Vec3::Zero(), 1.0), 0.05, cache, m);
  collide_sphere_sphere(Vec3(0, 0, 1.9), 1.0, Vec3::Zero(), 1.0, 0.05, direct);
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].gap, direct.points[0].gap);
  EXPECT_EQ(m.points[0].normal, Vec3::UnitZ());
  EXPECT_FALSE(cache.valid);  // only polyhedron pairs keep a plane
}

// Polyhedron A over sphere B: solved as (sphere, polyhedron) and flipped, so the normal
// points from B to A and the feature ids follow A and B.
TEST(Collide, PolyhedronSpherePairIsFlippedToThePairsOrder) {
  Box box(Vec3(0, 0, 1.45));
  const CollisionBody ball = sphere(Vec3::Zero(), 1.0);
  ContactManifold ab, ba;
  CommonPlaneCache cache;
  collide_pair(box.body, ball, 0.1, cache, ab);
  collide_pair(ball, box.body, 0.1, cache, ba);
  ASSERT_EQ(ab.count, 1);
  ASSERT_EQ(ba.count, 1);
  // 1e-12: the normal is a normalized difference of points of size ~1 (round-off only).
  EXPECT_NEAR(ab.points[0].normal.z(), 1.0, 1e-12);   // from the sphere (B) up to the box (A)
  EXPECT_NEAR(ba.points[0].normal.z(), -1.0, 1e-12);  // from the box (B) down to the sphere (A)
  EXPECT_EQ(ab.points[0].gap, ba.points[0].gap);
  EXPECT_EQ(ab.points[0].feature_a, ba.points[0].feature_b);
  EXPECT_EQ(ab.points[0].feature_b, ba.points[0].feature_a);
}

TEST(Collide, PolyhedronPairKeepsItsCommonPlane) {
  Box a(Vec3(0, 0, 1.02)), b(Vec3::Zero());
  ContactManifold m;
  CommonPlaneCache cache;
  collide_pair(a.body, b.body, 0.05, cache, m);
  EXPECT_EQ(m.count, 4);  // face on face: the four corners
  EXPECT_TRUE(cache.valid);
}

TEST(Collide, WallsByKind) {
  Box box(Vec3(0, 0, 0.49));
  ContactManifold mb, ms;
  collide_wall(box.body, Vec3::UnitZ(), Vec3::Zero(), 0.05, mb);
  collide_wall(sphere(Vec3(0, 0, 0.49), 0.5), Vec3::UnitZ(), Vec3::Zero(), 0.05, ms);
  EXPECT_EQ(mb.count, 4);
  EXPECT_EQ(ms.count, 1);
  // 1e-12: the gap is 0.49 - 0.5 in a few roundings of numbers of size ~1.
  EXPECT_NEAR(mb.points[0].gap, -0.01, 1e-12);
  EXPECT_NEAR(ms.points[0].gap, -0.01, 1e-12);
}

TEST(Collide, PlacedVertexCountFollowsTheShape) {
  SceneDef s;
  s.shapes.push_back(build_box(Vec3(1, 1, 1)).shape);
  BodyDef poly, ball;
  poly.kind = ShapeKind::Polyhedron;
  poly.shape = 0;
  EXPECT_EQ(placed_vertex_count(s, poly), 8);
  EXPECT_EQ(placed_vertex_count(s, ball), 0);
}

// Each kind fills its own part of the placed body: a sphere its radius at the scale, a
// polyhedron its vertices where the step keeps them and its view on them.
TEST(Collide, EachKindPlacesItsBody) {
  SceneDef s;
  s.shapes.push_back(build_box(Vec3(1, 1, 1)).shape);
  const Vec3 x(1, 2, 3);
  const Mat3 R = Eigen::AngleAxisd(0.3, Vec3(1, 2, 2).normalized()).toRotationMatrix();
  BodyDef ball;
  ball.radius = 0.5;
  const CollisionBody b = place_collision_body(s, ball, x, R, 1.5, nullptr);
  EXPECT_EQ(b.kind, ShapeKind::Sphere);
  EXPECT_EQ(b.center, x);
  EXPECT_EQ(b.radius, 0.75);
  EXPECT_EQ(b.poly.shape, nullptr);
  BodyDef poly;
  poly.kind = ShapeKind::Polyhedron;
  poly.shape = 0;
  std::vector<Vec3> vertices(static_cast<std::size_t>(placed_vertex_count(s, poly)));
  const CollisionBody p = place_collision_body(s, poly, x, R, 1.5, vertices.data());
  EXPECT_EQ(p.kind, ShapeKind::Polyhedron);
  EXPECT_EQ(p.center, x);
  EXPECT_EQ(p.poly.shape, &s.shapes[0]);
  EXPECT_EQ(p.poly.world_vertices, vertices.data());
  EXPECT_EQ(p.poly.center, x);
  EXPECT_EQ(p.poly.R, R);
  EXPECT_EQ(p.poly.scale, 1.5);
  for (std::size_t k = 0; k < vertices.size(); ++k) EXPECT_EQ(vertices[k], x + 1.5 * (R * s.shapes[0].vertices[k]));
  EXPECT_TRUE(manifold_reusable(p, p));
  EXPECT_FALSE(manifold_reusable(p, b));
  EXPECT_FALSE(manifold_reusable(b, b));
}

}  // namespace
}  // namespace ratchet

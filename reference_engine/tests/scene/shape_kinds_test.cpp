// The shape kinds' facts: every ShapeKind up to Count answers (a name, its two
// bodies.json fields, a placed body with its volume), so a kind added to ShapeKind is
// checked here without a new test; and the sphere's and polyhedron's answers.
#include "ratchet/scene/shape_kinds.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "ratchet/geometry/convex_polyhedron.hpp"

namespace ratchet {
namespace {

// One body of each kind: a sphere of radius 0.5 and a unit cube.
SceneDef one_of_each() {
  SceneDef s;
  s.shapes.push_back(build_box(Vec3(0.5, 0.5, 0.5)).shape);
  BodyDef sphere;
  sphere.kind = ShapeKind::Sphere;
  sphere.radius = 0.5;
  BodyDef cube;
  cube.kind = ShapeKind::Polyhedron;
  cube.shape = 0;
  s.bodies = {sphere, cube};
  return s;
}

TEST(ShapeKinds, EveryKindAnswers) {
  const SceneDef s = one_of_each();
  std::set<std::string> names;
  for (int k = 0; k < static_cast<int>(ShapeKind::Count); ++k) {
    const ShapeKind kind = static_cast<ShapeKind>(k);
    const ShapeKindFacts& facts = shape_kind(kind);
    SCOPED_TRACE(facts.name());
    names.insert(facts.name());
    BodyDef b;
    for (const BodyDef& d : s.bodies)
      if (d.kind == kind) b = d;
    ASSERT_EQ(b.kind, kind) << "one_of_each() needs a body of every kind";
    nlohmann::ordered_json j;
    facts.write_fields(b, j);
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j.begin().key(), "radius");  // the order bodies.json keeps
    EXPECT_TRUE(j.contains("shape"));
    PlacedBody p;
    facts.place(s, b, Vec3(1, 2, 3), Quat::Identity(), 2.0, p);
    EXPECT_FALSE(p.points.empty());
    EXPECT_GT(p.volume, 0.0);
    EXPECT_NE(p.faces != nullptr, p.sphere_radius > 0.0) << "a VTK file draws a body as faces or as a glyph";
  }
  EXPECT_EQ(names.size(), static_cast<std::size_t>(ShapeKind::Count));  // names tell the kinds apart
}

TEST(ShapeKinds, SphereIsARadiusAndAGlyph) {
  const SceneDef s = one_of_each();
  const ShapeKindFacts& k = shape_kind(ShapeKind::Sphere);
  EXPECT_STREQ(k.name(), "sphere");
  nlohmann::ordered_json j;
  k.write_fields(s.bodies[0], j);
  EXPECT_EQ(j.dump(), R"({"radius":0.5,"shape":null})");
  PlacedBody p;
  k.place(s, s.bodies[0], Vec3(0, 0, 1), Quat::Identity(), 2.0, p);
  EXPECT_EQ(p.sphere_radius, 1.0);
  EXPECT_EQ(p.top, 2.0);
  EXPECT_EQ(p.faces, nullptr);
  EXPECT_EQ(p.volume, 4.0 / 3.0 * M_PI);  // r = 1: the same products as the VTK file's
}

TEST(ShapeKinds, PolyhedronIsAShapeAndItsFaces) {
  const SceneDef s = one_of_each();
  const ShapeKindFacts& k = shape_kind(ShapeKind::Polyhedron);
  EXPECT_STREQ(k.name(), "polyhedron");
  nlohmann::ordered_json j;
  k.write_fields(s.bodies[1], j);
  EXPECT_EQ(j.dump(), R"({"radius":null,"shape":0})");
  PlacedBody p;
  k.place(s, s.bodies[1], Vec3(0, 0, 1), Quat::Identity(), 2.0, p);
  EXPECT_EQ(p.points.size(), 8u);
  EXPECT_EQ(p.faces, &s.shapes[0].faces);
  EXPECT_EQ(p.sphere_radius, 0.0);
  // 1e-12: the cube's top and volume are sums of a few roundings of numbers of size ~1.
  EXPECT_NEAR(p.top, 2.0, 1e-12);
  EXPECT_NEAR(p.volume, 8.0, 1e-12);
}

}  // namespace
}  // namespace ratchet

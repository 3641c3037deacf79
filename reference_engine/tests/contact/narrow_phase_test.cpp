#include "ratchet/contact/narrow_phase.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ratchet/core/random.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"
#include "ratchet/geometry/particle_generator.hpp"

namespace ratchet {
namespace {

struct Posed {
  PolyhedronBuild build;
  std::vector<Vec3> world;
  PolyhedronView view;
  Posed(PolyhedronBuild b, const Vec3& c, const Quat& q, double s) : build(std::move(b)) {
    for (const Vec3& v : build.shape.vertices) world.push_back(c + s * (q * v));
    view.shape = &build.shape;
    view.world_vertices = world.data();
    view.center = c;
    view.R = q.toRotationMatrix();
    view.scale = s;
  }
};

TEST(NarrowPhase, SphereSphereGapNormalAndMidpoint) {
  ContactManifold m;
  ASSERT_TRUE(collide_sphere_sphere(Vec3(0, 0, 2.1), 1.0, Vec3(0, 0, 0), 1.0, 0.2, m));
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].gap, 0.1, 1e-15);
  EXPECT_EQ(m.points[0].normal, Vec3::UnitZ());
  EXPECT_NEAR(m.points[0].point.z(), 1.05, 1e-15);
  EXPECT_FALSE(collide_sphere_sphere(Vec3(0, 0, 2.1), 1.0, Vec3(0, 0, 0), 1.0, 0.05, m));
  EXPECT_EQ(m.count, 0);
}

TEST(NarrowPhase, SpherePlaneOverlap) {
  ContactManifold m;
  ASSERT_TRUE(collide_sphere_plane(Vec3(1, 2, 0.4), 0.5, Vec3::UnitZ(), Vec3::Zero(), 0.0, m));
  EXPECT_NEAR(m.points[0].gap, -0.1, 1e-15);
  EXPECT_NEAR(m.points[0].point.z(), -0.05, 1e-15);
}

TEST(NarrowPhase, BoxFlatOnAPlaneGivesItsFourCorners) {
  Posed box(build_box(Vec3(0.5, 0.4, 0.3)), Vec3(0, 0, 0.3), Quat::Identity(), 1.0);
  ContactManifold m;
  ASSERT_TRUE(collide_polyhedron_plane(box.view, Vec3::UnitZ(), Vec3::Zero(), 0.01, m));
  ASSERT_EQ(m.count, 4);
  double area_x = 0, area_y = 0;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.points[i].gap, 0.0, 1e-15);
    area_x = std::max(area_x, std::abs(m.points[i].point.x()));
    area_y = std::max(area_y, std::abs(m.points[i].point.y()));
  }
  EXPECT_DOUBLE_EQ(area_x, 0.5);
  EXPECT_DOUBLE_EQ(area_y, 0.4);
}

TEST(NarrowPhase, TiltedBoxTouchesWithOneCorner) {
  const Quat q(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()));
  Posed box(build_box(Vec3(0.5, 0.5, 0.5)), Vec3(0, 0, 1.0), q, 1.0);
  double lowest = HUGE_VAL;
  for (const Vec3& v : box.world) lowest = std::min(lowest, v.z());
  ContactManifold m;
  ASSERT_TRUE(collide_polyhedron_plane(box.view, Vec3::UnitZ(), Vec3::Zero(), lowest + 0.01, m));
  ASSERT_EQ(m.count, 1);
  EXPECT_DOUBLE_EQ(m.points[0].gap, lowest);
}

// A body resting on an edge (two vertices 2e-6 into the plane) with four more vertices
// within the margin, 0.01-0.04 above it and far apart: the reduction to 4 points must
// keep both touching vertices and fill with the nearest of the others. Reducing all six
// by area kept three of the far ones and dropped a penetrating vertex (the floor
// contact of a settled bed then flipped between its two edge vertices every step).
TEST(NarrowPhase, PlaneReductionKeepsEveryTouchingVertex) {
  const std::vector<Vec3> pts{{-0.1, 0.0, -2e-6}, {0.1, 0.0, -2e-6}, {1.0, 1.0, 0.04}, {-1.0, 1.0, 0.03},
                              {-1.0, -1.0, 0.02}, {1.0, -1.0, 0.01}, {0.0, 0.0, 1.0}};
  PolyhedronBuild b = build_convex_polyhedron(pts);
  const Vec3 c = b.centroid;
  const Quat q(b.rotation);
  Posed body(std::move(b), c, q, 1.0);
  ASSERT_EQ(body.world.size(), pts.size());  // every point is a hull vertex, in input order
  ContactManifold m;
  ASSERT_TRUE(collide_polyhedron_plane(body.view, Vec3::UnitZ(), Vec3::Zero(), 0.05, m));
  ASSERT_EQ(m.count, 4);
  std::vector<std::int32_t> kept;
  for (int i = 0; i < m.count; ++i) kept.push_back(m.points[i].feature_a);
  std::sort(kept.begin(), kept.end());
  const std::vector<std::int32_t> expected{feature_id(FeatureKind::Vertex, 0), feature_id(FeatureKind::Vertex, 1),
                                          feature_id(FeatureKind::Vertex, 4), feature_id(FeatureKind::Vertex, 5)};
  EXPECT_EQ(kept, expected);
}

// Six vertices of a hexagonal prism lie on the plane: all touch, so the area reduction
// picks 4 of them spanning the face (the largest inscribed quadrilateral's corners lie
// on the hexagon), and no vertex of the top face is taken.
TEST(NarrowPhase, PlaneReductionOfAFlatFaceSpansIt) {
  std::vector<Vec3> pts;
  for (int k = 0; k < 6; ++k) {
    const double t = k * M_PI / 3.0;
    pts.emplace_back(std::cos(t), std::sin(t), 0.0);
    pts.emplace_back(std::cos(t), std::sin(t), 0.02);  // within the margin, not touching
  }
  PolyhedronBuild b = build_convex_polyhedron(pts);
  const Vec3 c = b.centroid;
  const Quat q(b.rotation);
  Posed body(std::move(b), c, q, 1.0);
  ContactManifold m;
  ASSERT_TRUE(collide_polyhedron_plane(body.view, Vec3::UnitZ(), Vec3::Zero(), 0.05, m));
  ASSERT_EQ(m.count, 4);
  double xmin = 1, xmax = -1;
  for (int i = 0; i < m.count; ++i) {
    EXPECT_NEAR(m.points[i].gap, 0.0, 1e-12);
    xmin = std::min(xmin, m.points[i].point.x());
    xmax = std::max(xmax, m.points[i].point.x());
  }
  EXPECT_GT(xmax - xmin, 1.0);  // spans the hexagon (width 2), not one side of it
}

// Sphere against a polyhedron: the gap must equal the distance to a dense sampling of
// the surface minus the radius (from outside), and the normal must point from the
// closest point to the centre.
TEST(NarrowPhase, SpherePolyhedronMatchesBruteForceDistance) {
  Rng rng(9);
  EllipsoidParticleSpec spec;
  for (int k = 0; k < 200; ++k) {
    Posed p(generate_ellipsoid_particle(spec, rng), Vec3(uniform(rng, -1, 1), 0, 0), uniform_rotation(rng),
            uniform(rng, 0.9, 1.1));
    const Vec3 c = p.view.center + uniform(rng, 0.3, 2.0) * uniform_unit_vector(rng);
    const double r = 0.2;
    ContactManifold m;
    if (!collide_sphere_polyhedron(c, r, p.view, 10.0, m)) continue;
    const ContactPoint& cp = m.points[0];
    // Brute force: min distance over every face triangle.
    double dmin = HUGE_VAL;
    bool inside = true;
    for (std::size_t f = 0; f < p.build.shape.faces.size(); ++f) {
      const auto& face = p.build.shape.faces[f];
      if (p.view.face_normal(static_cast<int>(f)).dot(c) > p.view.face_offset(static_cast<int>(f))) inside = false;
      for (std::size_t i = 1; i + 1 < face.size(); ++i)
        dmin = std::min(dmin, (c - closest_point_on_triangle(c, p.world[face[0]], p.world[face[i]],
                                                             p.world[face[i + 1]])).norm());
    }
    SCOPED_TRACE(k);
    if (inside) {
      EXPECT_LT(cp.gap, -r);
    } else {
      EXPECT_NEAR(cp.gap, dmin - r, 1e-12);  // same closest-point routine: round-off only
      EXPECT_NEAR(cp.normal.norm(), 1.0, 1e-14);
    }
  }
}

TEST(NarrowPhase, ClosestPointOnTriangleRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c), a);
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.2, 0.2, 3), a, b, c).isApprox(Vec3(0.2, 0.2, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(0.5, -2, 0), a, b, c).isApprox(Vec3(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Vec3(1, 1, 0), a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
}

}  // namespace
}  // namespace ratchet

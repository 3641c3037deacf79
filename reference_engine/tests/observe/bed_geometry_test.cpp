// Placed bodies, bed points and bed height: spheres at the particle scale, polyhedra
// rotated, fixed bodies left out, and the bed height of the highest point.
#include "ratchet/observe/bed_geometry.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "state_at_rest.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

// A sphere and a unit cube (centroid at the origin of its points).
SceneDef sphere_and_cube() {
  return build_scene(json::parse(R"({
    "name": "bed", "time": {"dt": 0.01, "duration": 1.0},
    "particles": {"bodies": [
      {"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]},
      {"shape": "polyhedron", "position": [3, 0, 2],
       "vertices": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[-0.5,0.5,-0.5],[0.5,0.5,-0.5],
                    [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[-0.5,0.5,0.5],[0.5,0.5,0.5]]}]}
  })"),
                     "bed.json");
}

State state_of(const SceneDef& s) { return test::state_at_rest(s); }

TEST(BedGeometry, SpherePointsLieOnItsScaledSurface) {
  const SceneDef s = sphere_and_cube();
  State st = state_of(s);
  st.s_p = 1.2;
  PlacedBody p;
  place_body(s, st, 0, p);
  ASSERT_EQ(p.points.size(), 14u);
  EXPECT_EQ(p.faces, nullptr);
  EXPECT_DOUBLE_EQ(p.sphere_radius, 0.6);
  for (const Vec3& q : p.points) EXPECT_NEAR((q - Vec3(0, 0, 1)).norm(), 0.6, 1e-15);
}

TEST(BedGeometry, PolyhedronPointsAreItsRotatedVertices) {
  const SceneDef s = sphere_and_cube();
  State st = state_of(s);
  // A quarter turn about x: the cube's vertices stay at +-0.5 about its centre.
  st.q[1] = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX())) * st.q[1];
  PlacedBody p;
  place_body(s, st, 1, p);
  ASSERT_EQ(p.points.size(), 8u);
  ASSERT_NE(p.faces, nullptr);
  EXPECT_EQ(p.sphere_radius, 0.0);
  EXPECT_EQ(p.faces->size(), s.shapes[static_cast<std::size_t>(s.bodies[1].shape)].faces.size());
  for (const Vec3& q : p.points) {
    const Vec3 d = q - Vec3(3, 0, 2);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(d[k]), 0.5, 1e-12) << k;
  }
}

TEST(BedGeometry, BedHeightIsTheHighestPointOfTheMovingBodies) {
  SceneDef s = sphere_and_cube();
  State st = state_of(s);
  EXPECT_NEAR(bed_height(s, st), 2.5, 1e-12);  // the cube's top face
  EXPECT_EQ(bed_points(s, st).size(), 14u + 8u);
  s.bodies[1].fixed = true;  // a fixed body is not bed
  EXPECT_EQ(bed_height(s, st), 1.5);
  EXPECT_EQ(bed_points(s, st).size(), 14u);
  st.s_p = 2.0;  // the sphere's top at z + s_p r
  EXPECT_EQ(bed_height(s, st), 2.0);
  EXPECT_EQ(body_scale(s.bodies[0], st.s_p), 2.0);
  EXPECT_EQ(body_scale(s.bodies[1], st.s_p), 1.0);  // fixed bodies keep scale 1
  st.x[0] = Vec3(0, 0, -5);  // below the floor: never below 0
  EXPECT_EQ(bed_height(s, st), 0.0);
}

// The bed height asks each kind for its top alone (ShapeKindFacts::top, at every step):
// the highest of the placed points, at many orientations and scales (to round-off: the
// top is n . v, the points R v, rounded differently).
TEST(BedGeometry, TheTopIsTheHighestPlacedPoint) {
  const SceneDef s = sphere_and_cube();
  State st = state_of(s);
  for (int k = 0; k < 200; ++k) {
    st.q[1] = Quat(Eigen::AngleAxisd(0.37 * k, Vec3(1.0, 0.3 * k, -0.2).normalized())) * st.q[1];
    st.x[1] = Vec3(3.0, 0.1 * k, 2.0 + 1e-3 * k);
    st.s_p = 1.0 + 1.7e-4 * k;
    const BodyDef& cube = s.bodies[1];
    PlacedBody p;
    place_body(s, st, 1, p);
    double highest = -HUGE_VAL;
    for (const Vec3& q : p.points) highest = std::max(highest, q.z());
    const double top = shape_kind(cube.kind).top(s, cube, st.x[1], st.q[1], body_scale(cube, st.s_p));
    ASSERT_NEAR(top, highest, 1e-14) << "orientation " << k;
    ASSERT_GT(top, st.x[1].z() + 0.49) << "orientation " << k;  // a cube's top vertex is at least 0.5 up
  }
}

// On a bed large enough for its parallel maximum (more than 256 bodies): the highest
// top, the same on 1, 2, 3 and 8 threads.
TEST(BedGeometry, TheBedHeightOfALargeBedIsTheSameOnAnyNumberOfThreads) {
  json bodies = json::array();
  for (int i = 0; i < 600; ++i)
    bodies.push_back({{"shape", "sphere"}, {"radius", 0.5},
                      {"position", {1.5 * (i % 25), 1.5 * (i / 25), 0.5 + 0.001 * ((i * 37) % 600)}}});
  const SceneDef s = build_scene(json{{"name", "bed"}, {"time", {{"dt", 0.01}, {"duration", 1.0}}},
                                      {"particles", {{"bodies", bodies}}}},
                                 "bed.json");
  const State st = state_of(s);
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2, 3, 8}) {
    omp_set_num_threads(threads);
    EXPECT_EQ(bed_height(s, st), 0.5 + 0.001 * 599 + 0.5) << threads << " threads";  // the body with (37 i) % 600 = 599
  }
  omp_set_num_threads(saved);
}

}  // namespace
}  // namespace ratchet

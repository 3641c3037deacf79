// The container drawing: every corner of the cone's mesh lies on the planes of its walls
// at the current scale, each polygon turns about its wall's normal, and a plane is a
// square of the stated size around its point.
#include "ratchet/observe/container_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ratchet {
namespace {

using nlohmann::json;

SceneDef cone(double angle_deg, int segments) {
  json j = json::parse(R"({
    "name": "mesh", "time": {"dt": 0.01, "duration": 1.0},
    "container": {"type": "cone", "bottom_radius": 3.0, "height": 5.0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]}]}
  })");
  j["container"]["opening_angle_deg"] = angle_deg;
  j["container"]["segments"] = segments;
  return build_scene(j, "mesh.json");
}

// Newell's normal of a polygon (its right-hand normal, any convex or not).
Vec3 newell(const ContainerMesh& m, std::size_t p) {
  Vec3 n = Vec3::Zero();
  const auto& f = m.polygons[p];
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Vec3& a = m.points[static_cast<std::size_t>(f[i])];
    const Vec3& b = m.points[static_cast<std::size_t>(f[(i + 1) % f.size()])];
    n += a.cross(b);
  }
  return n.normalized();
}

// The wall's point at container scale s_c (as World::wall_point).
Vec3 wall_point(const SceneDef& s, int w, double s_c) {
  const WallDef& wall = s.container.walls[static_cast<std::size_t>(w)];
  const Vec3& c0 = s.container.scale_center;
  return wall.expands ? Vec3(c0 + s_c * (wall.point - c0)) : wall.point;
}

void expect_on_walls(const SceneDef& s, const ContainerMesh& m, double s_c) {
  ASSERT_EQ(m.polygons.size(), m.wall.size());
  for (std::size_t p = 0; p < m.polygons.size(); ++p) {
    const int w = m.wall[p];
    const WallDef& wall = s.container.walls[static_cast<std::size_t>(w)];
    for (int k : m.polygons[p])
      EXPECT_NEAR(wall.normal.dot(m.points[static_cast<std::size_t>(k)] - wall_point(s, w, s_c)), 0.0, 1e-12)
          << "polygon " << p << " point " << k << " s_c " << s_c;
    EXPECT_NEAR((newell(m, p) - wall.normal).norm(), 0.0, 1e-12) << "polygon " << p;
  }
}

TEST(ContainerMesh, ConeCornersLieOnTheirWallsAtEveryScale) {
  for (const double angle : {0.0, 4.0, 30.0})
    for (const int n : {3, 16})
      for (const double s_c : {1.0, 1.1, 0.9}) {
        const SceneDef s = cone(angle, n);
        const ContainerMesh m = container_mesh(s, s_c);
        ASSERT_EQ(m.points.size(), 2u * static_cast<std::size_t>(n));
        ASSERT_EQ(m.polygons.size(), 1u + static_cast<std::size_t>(n));
        EXPECT_EQ(m.wall[0], 0);
        EXPECT_EQ(m.polygons[0].size(), static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) EXPECT_EQ(m.wall[static_cast<std::size_t>(k + 1)], k + 1);
        expect_on_walls(s, m, s_c);
        // Bottom corners at s_c r_c / cos(pi / N), top ones at height s_c H.
        EXPECT_NEAR(m.points[0].head<2>().norm(), s_c * 3.0 / std::cos(M_PI / n), 1e-12);
        EXPECT_NEAR(m.points[0].z(), 0.0, 1e-15);
        EXPECT_NEAR(m.points[static_cast<std::size_t>(n)].z(), s_c * 5.0, 1e-12);
        EXPECT_NEAR(m.points[static_cast<std::size_t>(n)].head<2>().norm(),
                    s_c * (3.0 + 5.0 * std::tan(angle * M_PI / 180.0)) / std::cos(M_PI / n), 1e-12);
      }
}

TEST(ContainerMesh, PlanesAreSquaresOfTheStatedSizeAroundTheirPoints) {
  const SceneDef s = build_scene(json::parse(R"({
    "name": "planes", "time": {"dt": 0.01, "duration": 1.0},
    "container": {"type": "planes", "planes": [
      {"normal": [0, 0, 1], "point": [0, 0, 0]},
      {"normal": [1, 1, 0.2], "point": [-3, 0, 0], "expands": true},
      {"normal": [0, -1, 0], "point": [0, 4, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]},
                             {"shape": "sphere", "radius": 0.25, "position": [1, 2, 2]}]}
  })"), "planes.json");
  EXPECT_DOUBLE_EQ(plane_patch_half_side(s, 0), 2.0 * (3.0 + 0.25));  // the second sphere is farther
  EXPECT_DOUBLE_EQ(plane_patch_half_side(s, 2), 2.0 * (std::sqrt(17.0) + 0.5));  // the first sphere
  for (const double s_c : {1.0, 1.2}) {
    const ContainerMesh m = container_mesh(s, s_c);
    ASSERT_EQ(m.polygons.size(), 3u);
    ASSERT_EQ(m.points.size(), 12u);
    expect_on_walls(s, m, s_c);
    for (int w = 0; w < 3; ++w) {
      const double f = s.container.walls[static_cast<std::size_t>(w)].expands ? s_c : 1.0;
      const double h = f * plane_patch_half_side(s, w);
      Vec3 centre = Vec3::Zero();
      for (int k : m.polygons[static_cast<std::size_t>(w)]) centre += m.points[static_cast<std::size_t>(k)] / 4.0;
      EXPECT_NEAR((centre - wall_point(s, w, s_c)).norm(), 0.0, 1e-12);
      const auto& q = m.polygons[static_cast<std::size_t>(w)];
      for (int i = 0; i < 4; ++i) {  // a square of side 2h: equal sides, right angles
        const Vec3 e = m.points[static_cast<std::size_t>(q[static_cast<std::size_t>((i + 1) % 4)])] -
                       m.points[static_cast<std::size_t>(q[static_cast<std::size_t>(i)])];
        const Vec3 next = m.points[static_cast<std::size_t>(q[static_cast<std::size_t>((i + 2) % 4)])] -
                          m.points[static_cast<std::size_t>(q[static_cast<std::size_t>((i + 1) % 4)])];
        EXPECT_NEAR(e.norm(), 2.0 * h, 1e-12);
        EXPECT_NEAR(e.dot(next), 0.0, 1e-9);
      }
    }
  }
  // A plane that does not expand stays where it is at any scale.
  EXPECT_EQ(container_mesh(s, 1.0).points[0], container_mesh(s, 1.5).points[0]);
  EXPECT_NE(container_mesh(s, 1.0).points[4], container_mesh(s, 1.5).points[4]);
}

TEST(ContainerMesh, NoContainerNoMesh) {
  SceneDef s = build_scene(json::parse(R"({
    "name": "free", "time": {"dt": 0.01, "duration": 1.0},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]}]}
  })"), "free.json");
  const ContainerMesh m = container_mesh(s, 1.3);
  EXPECT_TRUE(m.points.empty());
  EXPECT_TRUE(m.polygons.empty());
  EXPECT_TRUE(m.wall.empty());
}

}  // namespace
}  // namespace ratchet

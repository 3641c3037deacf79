// Side-segment forces and side-wall contacts from a step's solved contacts.
#include "ratchet/observe/wall_forces.hpp"

#include <gtest/gtest.h>

namespace ratchet {
namespace {

SceneDef cone() {
  return build_scene(nlohmann::json::parse(R"({
    "name": "cone", "time": {"dt": 0.5, "duration": 1.0},
    "container": {"type": "cone", "bottom_radius": 3.0, "segments": 8},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]}
  })"),
                     "cone.json");
}

SolverContact contact(int a, int b, double lambda_n, double z) {
  SolverContact c;
  c.a = a;
  c.b = b;
  c.lambda = Vec3(lambda_n, 0.3, 0.0);  // tangential parts do not count
  c.geometry.point = Vec3(0, 0, z);
  return c;
}

TEST(WallForces, SideSegmentsGetTheirContactsNormalForces) {
  const SceneDef s = cone();
  const std::vector<int> sides = side_wall_indices(s);
  ASSERT_EQ(sides.size(), 8u);
  for (int w : sides) EXPECT_EQ(s.container.walls[static_cast<std::size_t>(w)].role, WallRole::Side);
  int bottom = -1;
  for (std::size_t w = 0; w < s.container.walls.size(); ++w)
    if (s.container.walls[w].role == WallRole::Bottom) bottom = static_cast<int>(w);
  ASSERT_GE(bottom, 0);
  // Two contacts on segment 2, one on segment 5, one on the floor, one between bodies.
  const std::vector<SolverContact> cs = {contact(0, -1 - sides[2], 1.0, 0.2), contact(0, -1 - sides[5], 2.0, 0.4),
                                         contact(0, -1 - sides[2], 3.0, 0.6), contact(0, -1 - bottom, 5.0, 0.0),
                                         contact(0, 1, 7.0, 0.5)};
  const std::vector<double> f = side_segment_forces(s, cs);
  ASSERT_EQ(f.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(f[k], k == 2 ? 8.0 : k == 5 ? 4.0 : 0.0) << k;  // lambda / h, h = 0.5
  std::vector<double> z = {9.0}, force;
  side_wall_contacts(s, cs, z, force);
  EXPECT_EQ(z, (std::vector<double>{0.2, 0.4, 0.6}));
  EXPECT_EQ(force, (std::vector<double>{2.0, 4.0, 6.0}));
}

}  // namespace
}  // namespace ratchet

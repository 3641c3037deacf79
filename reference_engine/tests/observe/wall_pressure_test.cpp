#include "ratchet/observe/wall_pressure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "ratchet/observe/bed_geometry.hpp"

namespace ratchet {
namespace {

// All tolerances below are relative 1e-12 unless stated: the quantities are a handful
// of floating-point operations, so only rounding separates them from the formula.
constexpr double kRel = 1e-12;

TEST(FrustumSideArea, CylinderIsPerimeterTimesHeight) {
  // theta = 0: N rectangles of width 2 a tan(pi/N) and height H.
  for (int n : {3, 4, 16}) {
    const double a = 8.5, h = 12.0;
    const double expected = n * 2.0 * a * std::tan(M_PI / n) * h;
    EXPECT_NEAR(frustum_side_area(a, 0.0, n, h), expected, kRel * expected) << n;
  }
  // Square (N = 4, a = 1): perimeter 8, H = 3 -> 24, by hand.
  EXPECT_NEAR(frustum_side_area(1.0, 0.0, 4, 3.0), 24.0, kRel * 24.0);
}

TEST(FrustumSideArea, SquareConeByHand) {
  // N = 4, a0 = 1, theta = 45 deg, H = 1: a1 = 2, so each face is a trapezoid with
  // parallel sides 2 and 4 and slant height sqrt(2): area 3 sqrt(2); four of them.
  const double expected = 12.0 * std::sqrt(2.0);
  EXPECT_NEAR(frustum_side_area(1.0, 45.0, 4, 1.0), expected, kRel * expected);
}

TEST(FrustumSideArea, ManySegmentsApproachTheRoundCone) {
  // N tan(pi/N) -> pi: lateral area of a round frustum pi (r0 + r1) H / cos(theta).
  const double a0 = 8.5, th = 8.0 * M_PI / 180.0, h = 10.0, a1 = a0 + h * std::tan(th);
  const double round = M_PI * (a0 + a1) * h / std::cos(th);
  // N tan(pi/N) = pi (1 + x^2 / 3 + 2 x^4 / 15 + ...), x = pi/N: at N = 1000 the
  // excess is 3.3e-6 relative; with the x^2 term included the rest is 1.3e-11, so
  // 1e-9 relative leaves room for rounding only. The N = 16 container is 1.3 % above.
  const double x = M_PI / 1000.0;
  EXPECT_GT(frustum_side_area(a0, 8.0, 1000, h), round);
  EXPECT_NEAR(frustum_side_area(a0, 8.0, 1000, h), round * (1.0 + x * x / 3.0), 1e-9 * round);
  EXPECT_GT(frustum_side_area(a0, 8.0, 16, h), round * 1.01);
}

TEST(FrustumSideArea, ZeroHeightAndInvalidInput) {
  EXPECT_EQ(frustum_side_area(8.5, 4.0, 16, 0.0), 0.0);
  EXPECT_THROW(frustum_side_area(8.5, 0.0, 2, 1.0), std::invalid_argument);
  EXPECT_THROW(frustum_side_area(0.0, 0.0, 16, 1.0), std::invalid_argument);
  EXPECT_THROW(frustum_side_area(8.5, 0.0, 16, -1.0), std::invalid_argument);
  EXPECT_THROW(frustum_side_area(8.5, 90.0, 16, 1.0), std::invalid_argument);
  EXPECT_THROW(frustum_side_area(1.0, -45.0, 4, 2.0), std::invalid_argument);  // closes at z = 1
  EXPECT_THROW(frustum_side_area(8.5, std::nan(""), 16, 1.0), std::invalid_argument);
}

TEST(WallLoad, PressureIsSideForceOverWettedArea) {
  std::vector<double> seg(16);
  for (int i = 0; i < 16; ++i) seg[static_cast<std::size_t>(i)] = 1.0 + i;  // sum 136
  const WallLoad load = wall_load(seg, 42.0, 8.5, 0.0, 16, 10.0);
  const double area = 16 * 2.0 * 8.5 * std::tan(M_PI / 16) * 10.0;
  EXPECT_EQ(load.segment_force, seg);
  EXPECT_NEAR(load.side_force, 136.0, kRel * 136.0);
  EXPECT_EQ(load.bottom_force, 42.0);
  EXPECT_NEAR(load.wetted_area, area, kRel * area);
  EXPECT_NEAR(load.pressure, 136.0 / area, kRel * 136.0 / area);
}

TEST(WallLoad, ZeroHeightGivesZeroPressureAndWrongSegmentCountThrows) {
  const WallLoad load = wall_load(std::vector<double>(16, 1.0), 0.0, 8.5, 4.0, 16, 0.0);
  EXPECT_EQ(load.wetted_area, 0.0);
  EXPECT_EQ(load.pressure, 0.0);
  EXPECT_THROW(wall_load(std::vector<double>(15, 1.0), 0.0, 8.5, 4.0, 16, 1.0), std::invalid_argument);
}

TEST(WallStressProfile, CylinderBandsHaveEqualArea) {
  // Cylinder, N = 4, a = 1: each band of height 1 (H = 4, 4 bands) has area 8.
  const std::vector<double> z = {0.5, 0.7, 1.2, 3.9, 2.0};  // 2.0 lies on a band boundary: band 2
  const std::vector<double> f = {1.0, 3.0, 8.0, 16.0, 4.0};
  const std::vector<double> s = wall_stress_profile(z, f, 1.0, 0.0, 4, 4.0, 4);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_NEAR(s[0], 4.0 / 8.0, kRel);
  EXPECT_NEAR(s[1], 8.0 / 8.0, kRel);
  EXPECT_NEAR(s[2], 4.0 / 8.0, kRel);
  EXPECT_NEAR(s[3], 16.0 / 8.0, kRel);
}

TEST(WallStressProfile, ConeBandsUseTheirOwnAreaAndConserveForce) {
  // Square cone: N = 4, a0 = 1, theta = 45 deg, H = 2, 2 bands. Band 0: apothems 1 -> 2,
  // area 12 sqrt 2 (hand case above); band 1: apothems 2 -> 3, area 4 * 5 * sqrt 2 = 20 sqrt 2.
  const std::vector<double> z = {0.3, 1.5, -0.01, 2.0};  // below 0 -> band 0; z = H -> last band
  const std::vector<double> f = {6.0, 10.0, 1.0, 4.0};
  const std::vector<double> s = wall_stress_profile(z, f, 1.0, 45.0, 4, 2.0, 2);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0], 7.0 / (12.0 * std::sqrt(2.0)), kRel);
  EXPECT_NEAR(s[1], 14.0 / (20.0 * std::sqrt(2.0)), kRel);
  // The band areas add up to the whole frustum and the forces are all counted.
  const double total = s[0] * 12.0 * std::sqrt(2.0) + s[1] * 20.0 * std::sqrt(2.0);
  EXPECT_NEAR(total, 21.0, kRel * 21.0);
  EXPECT_NEAR(12.0 * std::sqrt(2.0) + 20.0 * std::sqrt(2.0), frustum_side_area(1.0, 45.0, 4, 2.0), kRel * 50.0);
}

TEST(WallStressProfile, EmptyBandsAreZeroAndBadInputThrows) {
  const std::vector<double> s = wall_stress_profile({}, {}, 8.5, 2.0, 16, 10.0, 5);
  EXPECT_EQ(s, std::vector<double>(5, 0.0));
  EXPECT_THROW(wall_stress_profile({1.0}, {}, 8.5, 2.0, 16, 10.0, 5), std::invalid_argument);
  EXPECT_THROW(wall_stress_profile({1.0}, {1.0}, 8.5, 2.0, 16, 10.0, 0), std::invalid_argument);
  EXPECT_THROW(wall_stress_profile({1.0}, {1.0}, 8.5, 2.0, 16, 0.0, 5), std::invalid_argument);
  EXPECT_THROW(wall_stress_profile({std::nan("")}, {1.0}, 8.5, 2.0, 16, 10.0, 5), std::invalid_argument);
}

// The scene's wetted area is frustum_side_area at the container scale, bit for bit
// (one formula), and 0 where there is no wetted wall.
TEST(WettedSideArea, IsTheFrustumAtTheContainerScale) {
  const SceneDef s = build_scene(nlohmann::json::parse(R"({
    "name": "cone", "time": {"dt": 0.01, "duration": 1.0},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 6.0, "segments": 12},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.5]}]}
  })"),
                                 "cone.json");
  State st;
  st.x = {Vec3(0, 0, 0.5)};
  st.q = {Quat::Identity()};
  st.s_c = 1.01;
  EXPECT_EQ(wetted_side_area(s, st, 2.0), frustum_side_area(1.01 * 3.0, 6.0, 12, 2.0));
  EXPECT_EQ(wetted_side_area(s, st, 0.0), 0.0);
  EXPECT_EQ(wetted_side_area(s, st, -1.0), 0.0);
  // Pressure: the side force over the area up to the bed height (the sphere's top, 1).
  EXPECT_EQ(side_wall_pressure(s, st, 7.0), 7.0 / frustum_side_area(1.01 * 3.0, 6.0, 12, 1.0));
  st.x[0].z() = -2.0;  // no bed above the floor: no area, no pressure
  EXPECT_EQ(side_wall_pressure(s, st, 7.0), 0.0);
  SceneDef planes = s;
  planes.container.type = ContainerDef::Type::Planes;
  st.x[0].z() = 0.5;
  EXPECT_EQ(wetted_side_area(planes, st, 2.0), 0.0);
  EXPECT_EQ(side_wall_pressure(planes, st, 7.0), 0.0);
}

}  // namespace
}  // namespace ratchet

#include "ratchet/contact/manifold_reduction.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ratchet {
namespace {

TEST(ManifoldReduction, KeepsUpToFourUnchanged) {
  std::vector<ContactPoint> c(3);
  for (int i = 0; i < 3; ++i) c[i].point = Vec3(i, 0, 0);
  ContactManifold m;
  reduce_manifold(c, m);
  EXPECT_EQ(m.count, 3);
}

TEST(ManifoldReduction, OctagonReducesToADeepestPointAndAWideQuadrilateral) {
  std::vector<ContactPoint> c(8);
  for (int i = 0; i < 8; ++i) {
    c[i].point = Vec3(std::cos(i * M_PI / 4), std::sin(i * M_PI / 4), 0);
    c[i].normal = Vec3::UnitZ();
    c[i].gap = i == 5 ? -0.01 : 0.0;
    c[i].feature_a = i;
  }
  ContactManifold m;
  reduce_manifold(c, m);
  ASSERT_EQ(m.count, 4);
  EXPECT_EQ(m.points[0].feature_a, 5);  // the deepest first
  // The quadrilateral spans the octagon: its area is the inscribed square's, 2.
  double area = 0;
  std::vector<Vec3> p;
  for (int i = 0; i < 4; ++i) p.push_back(m.points[i].point);
  std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) { return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x()); });
  for (int i = 0; i < 4; ++i) area += 0.5 * p[i].cross(p[(i + 1) % 4]).z();
  EXPECT_NEAR(area, 2.0, 1e-12);
}

// A tilted octagonal region: two adjacent corners pressed in, the others 1e-5 to 1e-4
// clear. The plain reduction keeps the deepest corner and spans the octagon, dropping
// the other pressed corner; touching-first keeps both and fills with the nearest.
TEST(ManifoldReduction, TouchingFirstKeepsEveryPressedCorner) {
  std::vector<ContactPoint> c(8);
  for (int i = 0; i < 8; ++i) {
    c[i].point = Vec3(std::cos((i + 0.5) * M_PI / 4), std::sin((i + 0.5) * M_PI / 4), 0);
    c[i].normal = Vec3::UnitZ();
    // Tilted down towards -y (corners 5 and 6 lowest), slightly towards -x (no ties).
    c[i].gap = 1e-4 * (1.0 + c[i].point.y()) + 1e-6 * c[i].point.x() - 1e-5;
    c[i].feature_a = i;
  }
  for (int i = 0; i < 8; ++i) ASSERT_EQ(c[i].gap < 0.0, i == 5 || i == 6) << i;
  ContactManifold plain;
  reduce_manifold(c, plain);
  std::vector<int> kept_plain;
  for (int i = 0; i < plain.count; ++i) kept_plain.push_back(plain.points[i].feature_a);
  std::sort(kept_plain.begin(), kept_plain.end());
  EXPECT_FALSE(std::binary_search(kept_plain.begin(), kept_plain.end(), 6));  // the flaw fixed below

  ContactManifold m;
  std::vector<ContactPoint> work = c;
  reduce_touching_first(work, 0.0, m);
  ASSERT_EQ(m.count, 4);
  std::vector<int> kept;
  for (int i = 0; i < m.count; ++i) kept.push_back(m.points[i].feature_a);
  std::sort(kept.begin(), kept.end());
  // 5 and 6 pressed in; 4 and 7 (gaps 5.1e-5 and 5.3e-5) are the nearest of the rest.
  EXPECT_EQ(kept, (std::vector<int>{4, 5, 6, 7}));
}

// More than 4 touching points: they are reduced by area among themselves and the
// points beyond `touch` are left out, whatever their spread.
TEST(ManifoldReduction, TouchingFirstReducesTheTouchingByArea) {
  std::vector<ContactPoint> c;
  for (int i = 0; i < 6; ++i) {
    ContactPoint p;
    p.point = Vec3(std::cos(i * M_PI / 3), std::sin(i * M_PI / 3), 0);
    p.normal = Vec3::UnitZ();
    p.gap = 0.0;
    p.feature_a = i;
    c.push_back(p);
  }
  for (int i = 0; i < 2; ++i) {  // far out, clear of the other body
    ContactPoint p;
    p.point = Vec3(i == 0 ? 5.0 : -5.0, 0.0, 0.0);
    p.normal = Vec3::UnitZ();
    p.gap = 0.01;
    p.feature_a = 10 + i;
    c.insert(c.begin() + 2 * i, p);
  }
  ContactManifold m;
  reduce_touching_first(c, 1e-6, m);
  ASSERT_EQ(m.count, 4);
  for (int i = 0; i < 4; ++i) EXPECT_LT(m.points[i].feature_a, 6);
}

}  // namespace
}  // namespace ratchet

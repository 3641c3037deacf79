#include "ratchet/contact/manifold_reduction.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace ratchet

#include "ratchet/geometry/particle_generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ratchet {
namespace {

// Vertices are r/max(axes) * axes .* u with |u| = 1 up to rounding; a dozen
// operations on O(1) values.
constexpr double kRound = 1e-12;

TEST(EllipsoidParticleGenerator, RadiusStatisticsAndVertexCounts) {
  const EllipsoidParticleSpec spec;  // paper defaults: 20 vertices, axes (1, .95, .9), r in [.5, 1]
  Rng rng(2024);
  const int n = 2000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    double r = -1.0;
    const auto p = generate_ellipsoid_particle(spec, rng, &r);
    EXPECT_GE(r, spec.radius_min);
    EXPECT_LE(r, spec.radius_max);
    EXPECT_LE(p.shape.vertices.size(), static_cast<std::size_t>(spec.vertices));
    EXPECT_GE(p.shape.vertices.size(), 4u);
    sum += r;
  }
  // Uniform radius: sd = (max - min)/sqrt(12); a fixed seed within 4 standard errors.
  const double se = (spec.radius_max - spec.radius_min) / std::sqrt(12.0) / std::sqrt(n);
  EXPECT_NEAR(sum / n, 0.5 * (spec.radius_min + spec.radius_max), 4.0 * se);
}

TEST(EllipsoidParticleGenerator, VerticesLieOnTheScaledEllipsoid) {
  EllipsoidParticleSpec spec;
  spec.vertices = 30;
  Rng rng(99);
  double reach[3] = {0, 0, 0};  // max |coordinate| / r over all particles, per axis
  for (int i = 0; i < 500; ++i) {
    double r = 0.0;
    const auto p = generate_ellipsoid_particle(spec, rng, &r);
    const Vec3 semi = r / spec.axes.maxCoeff() * spec.axes;
    for (const Vec3& v : p.shape.vertices) {
      const Vec3 x = p.centroid + p.rotation * v;  // back to the generator's frame
      EXPECT_NEAR(x.cwiseQuotient(semi).squaredNorm(), 1.0, kRound);
      EXPECT_LE(x.norm(), r * (1.0 + kRound));
      for (int k = 0; k < 3; ++k) reach[k] = std::max(reach[k], std::abs(x[k]) / r);
    }
    // Body frame is centred on the hull centroid, not the ellipsoid centre: the
    // bounding radius may exceed r, by at most the centroid offset.
    EXPECT_LE(p.shape.bounding_radius, r + p.centroid.norm() + kRound);
    EXPECT_LT(p.shape.volume, 4.0 / 3.0 * M_PI * semi.prod());  // inscribed in the ellipsoid
  }
  // The largest semi-axis is r, the others 0.95 r and 0.9 r; with 15000 directions
  // P(no |u_k| > 0.995) = 0.995^15000 ~ e^-75, so each axis is reached to 0.5%.
  EXPECT_GT(reach[0], 0.995);
  EXPECT_LE(reach[0], 1.0 + kRound);
  EXPECT_GT(reach[1], 0.95 * 0.995);
  EXPECT_LE(reach[1], 0.95 + kRound);
  EXPECT_GT(reach[2], 0.9 * 0.995);
  EXPECT_LE(reach[2], 0.9 + kRound);
}

TEST(EllipsoidParticleGenerator, SameSeedSameParticlesDifferentSeedsDiffer) {
  const EllipsoidParticleSpec spec;
  Rng a(17), b(17), c(18);
  for (int i = 0; i < 20; ++i) {
    double ra = 0, rb = 0, rc = 0;
    const auto pa = generate_ellipsoid_particle(spec, a, &ra);
    const auto pb = generate_ellipsoid_particle(spec, b, &rb);
    const auto pc = generate_ellipsoid_particle(spec, c, &rc);
    EXPECT_EQ(ra, rb);
    EXPECT_NE(ra, rc);
    ASSERT_EQ(pa.shape.vertices.size(), pb.shape.vertices.size());
    for (std::size_t k = 0; k < pa.shape.vertices.size(); ++k)
      EXPECT_EQ(pa.shape.vertices[k], pb.shape.vertices[k]);  // bit-identical
    EXPECT_EQ(pa.shape.faces, pb.shape.faces);
    EXPECT_NE(pa.shape.volume, pc.shape.volume);
  }
}

TEST(EllipsoidParticleGenerator, ConsumesOneRadiusAndTwoDrawsPerVertex) {
  EllipsoidParticleSpec spec;
  spec.vertices = 12;
  Rng rng(1), reference(1);
  generate_ellipsoid_particle(spec, rng);  // radius_out is optional
  reference.discard(1 + 2 * 12);
  EXPECT_EQ(rng, reference);
}

// Four vertices give slivers now and then (a tetrahedron of nearly coplanar points):
// they are drawn again, so every particle has an inradius of at least 5 % of r, and the
// count says how many were redrawn.
TEST(EllipsoidParticleGenerator, SliversAreDrawnAgain) {
  EllipsoidParticleSpec spec;
  spec.vertices = 4;
  Rng rng(7);
  int redrawn = 0;
  double thinnest = HUGE_VAL;
  for (int i = 0; i < 2000; ++i) {
    double r = 0.0;
    const auto p = generate_ellipsoid_particle(spec, rng, &r, &redrawn);
    thinnest = std::min(thinnest, p.shape.min_face_offset / r);
  }
  EXPECT_GE(thinnest, kMinInradius);
  EXPECT_GT(redrawn, 0);      // 4-vertex hulls below 5 % of r are common enough in 2000
  EXPECT_LT(redrawn, 2000);   // but far from the rule
}

// The paper's 20-vertex hulls are never slivers: no redraw, so the stream of numbers
// and every particle are what they were before the rule.
TEST(EllipsoidParticleGenerator, ThePapersParticlesAreNeverRedrawn) {
  const EllipsoidParticleSpec spec;
  Rng rng(2024), reference(2024);
  int redrawn = 0;
  for (int i = 0; i < 2000; ++i) generate_ellipsoid_particle(spec, rng, nullptr, &redrawn);
  EXPECT_EQ(redrawn, 0);
  reference.discard(2000 * (1 + 2 * 20));
  EXPECT_EQ(rng, reference);
}

TEST(EllipsoidParticleGenerator, RejectsBadSpec) {
  Rng rng(1);
  auto rejects = [&](auto change) {
    EllipsoidParticleSpec spec;
    change(spec);
    EXPECT_THROW(generate_ellipsoid_particle(spec, rng), std::invalid_argument);
  };
  rejects([](EllipsoidParticleSpec& s) { s.vertices = 3; });
  rejects([](EllipsoidParticleSpec& s) { s.radius_min = 0.0; });
  rejects([](EllipsoidParticleSpec& s) { s.radius_min = 1.5; });  // above radius_max
  rejects([](EllipsoidParticleSpec& s) { s.radius_max = INFINITY; });
  rejects([](EllipsoidParticleSpec& s) { s.axes = Vec3(1, -0.9, 0.9); });
  rejects([](EllipsoidParticleSpec& s) { s.axes = Vec3(1, std::nan(""), 0.9); });
  // Equal radius bounds are allowed: every particle has that radius.
  EllipsoidParticleSpec fixed;
  fixed.radius_min = fixed.radius_max = 0.7;
  double r = 0;
  generate_ellipsoid_particle(fixed, rng, &r);
  EXPECT_EQ(r, 0.7);
}

}  // namespace
}  // namespace ratchet

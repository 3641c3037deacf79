// libFuzzer target: the polyhedron-polyhedron narrow phase against the brute-force SAT
// oracle of the contact tests (tests/contact/sat_oracle.hpp). docs/validation.md s. 9.
//
// Input bytes -> two convex hulls of 4-16 points each and a relative pose:
//   byte 0      : n_a - 4 (mod 13), byte 1: n_b - 4 (mod 13), byte 2: flags
//   then points : 3 coordinates each. flags bit 0 set: each coordinate is an int8 / 64
//                 (a coarse lattice: coplanar faces, parallel edges and exact ties are
//                 common, the hard cases of the search); clear: a uint32 mapped to
//                 [-1, 1] (generic positions).
//   then pose   : a quaternion (4 x int8, normalised; ~0: identity) and a translation
//                 (3 x int16 / 16384, so |t_i| < 2: the hulls are O(1), so many
//                 poses touch) for A; B stays at the origin, identity.
//                 flags bit 1 set: A is moved along the translation direction so that
//                 the oracle's s(n) along it is a small signed gap (int16 / 2^20): near
//                 touching, the contact band and the margin boundary.
//   flags bit 2 : the pair is collided a second time with the warm cache (same pose).
// Clouds that cannot span a solid (point_cloud_defect) are skipped.
//
// Properties (o = oracle_common_plane: o.gap is the exact signed distance, -depth when
// overlapping):
//   * every contact point, normal and gap is finite; normals are unit;
//   * o.gap > margin + tol: no contact point;
//   * o.gap < -tol: at least one contact point, and the smallest point gap is within
//     tol + band of o.gap.
// tol = 1e-7 x L, L = 1 + the larger bounding radius (coordinates are O(1)): the unit
// tests' gap agreement is 1e-9 (tests/contact/common_plane_test.cpp, kGapTol) for
// well-shaped particles; the fuzzer's hulls include slivers down to the 1e-9 flatness
// that point_cloud_defect admits, whose planes are conditioned ~100x worse, and 1e-7 is
// still 1e4 below the contact band. band = kBand x the smaller bounding radius
// (contact/common_plane_detail.hpp, 1e-3 r): the engine takes every vertex within the
// band of its supporting plane as part of the contact feature and lifts the clipped
// region's corners onto that feature as if it were flat, so when the feature bends
// (a ridge inside the band) the deepest point of the true region can lie between two
// corners and the manifold's deepest gap may miss -depth by up to about the band, by design.
// The minimum-translation witnesses of a polytope pair project onto the same point of
// the plane, so with a flat feature the deepest corner reaches -depth exactly. A
// violation aborts with the numbers printed, so libFuzzer saves the input.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "ratchet/contact/collide.hpp"
#include "ratchet/contact/common_plane_detail.hpp"  // kBand
#include "ratchet/geometry/convex_polyhedron.hpp"
#include "sat_oracle.hpp"

namespace {

using namespace ratchet;

constexpr double kMargin = 0.05;  // the scenes' default contact margin (SolverSettings)

std::vector<Vec3> read_cloud(FuzzedDataProvider& in, int n, bool lattice) {
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = lattice ? in.ConsumeIntegral<std::int8_t>() / 64.0
                     : in.ConsumeIntegral<std::uint32_t>() / 2147483647.5 - 1.0;
    pts.push_back(p);
  }
  return pts;
}

struct Placed {
  const ConvexPolyhedron* shape = nullptr;
  std::vector<Vec3> world;
  CollisionBody body;
  void place(const ConvexPolyhedron& s, const Vec3& c, const Mat3& R) {
    shape = &s;
    world.resize(s.vertices.size());
    for (std::size_t i = 0; i < world.size(); ++i) world[i] = c + R * s.vertices[i];
    body.kind = ShapeKind::Polyhedron;
    body.center = c;
    body.poly.shape = &s;
    body.poly.world_vertices = world.data();
    body.poly.center = c;
    body.poly.R = R;
    body.poly.scale = 1.0;
  }
};

[[noreturn]] void violation(const char* what, const test::OracleResult& o, const ContactManifold& m,
                            double tol) {
  std::fprintf(stderr, "narrow_phase_fuzz: PROPERTY VIOLATED: %s\n", what);
  std::fprintf(stderr, "  oracle: gap %.17g (sat %.17g, separated %d) normal %.17g %.17g %.17g; tol %.3g\n",
               o.gap, o.sat_gap, o.separated ? 1 : 0, o.normal.x(), o.normal.y(), o.normal.z(), tol);
  std::fprintf(stderr, "  engine: %d points\n", m.count);
  for (int i = 0; i < m.count; ++i) {
    const ContactPoint& c = m.points[static_cast<std::size_t>(i)];
    std::fprintf(stderr, "    gap %.17g normal %.17g %.17g %.17g point %.17g %.17g %.17g\n", c.gap,
                 c.normal.x(), c.normal.y(), c.normal.z(), c.point.x(), c.point.y(), c.point.z());
  }
  std::abort();
}

void check(const test::OracleResult& o, const ContactManifold& m, double tol, double band) {
  if (m.count < 0 || m.count > 4) violation("manifold count outside [0, 4]", o, m, tol);
  double min_gap = HUGE_VAL;
  for (int i = 0; i < m.count; ++i) {
    const ContactPoint& c = m.points[static_cast<std::size_t>(i)];
    if (!c.point.allFinite() || !c.normal.allFinite() || !std::isfinite(c.gap))
      violation("non-finite contact output", o, m, tol);
    if (std::abs(c.normal.norm() - 1.0) > 1e-9) violation("contact normal not unit", o, m, tol);
    min_gap = std::min(min_gap, c.gap);
  }
  if (o.gap > kMargin + tol && m.count != 0) violation("contact points for a pair apart by more than the margin", o, m, tol);
  if (o.gap < -tol) {
    if (m.count == 0) violation("no contact point for an overlapping pair", o, m, tol);
    if (std::abs(min_gap - o.gap) > tol + band)
      violation("deepest contact gap differs from the SAT depth by more than tol + band", o, m, tol + band);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const int na = 4 + in.ConsumeIntegral<std::uint8_t>() % 13;
  const int nb = 4 + in.ConsumeIntegral<std::uint8_t>() % 13;
  const std::uint8_t flags = in.ConsumeIntegral<std::uint8_t>();
  const bool lattice = (flags & 1) != 0;
  const std::vector<Vec3> pa = read_cloud(in, na, lattice);
  const std::vector<Vec3> pb = read_cloud(in, nb, lattice);
  if (!point_cloud_defect(pa).empty() || !point_cloud_defect(pb).empty()) return 0;

  PolyhedronBuild a, b;
  try {
    a = build_convex_polyhedron(pa, "A");
    b = build_convex_polyhedron(pb, "B");
  } catch (const std::invalid_argument&) {
    return 0;  // documented rejection (Qhull found the cloud flat after all)
  }

  // Named draws: the order of evaluation of function arguments is unspecified, and a
  // replay built by another compiler must decode the same pose.
  const double qw = in.ConsumeIntegral<std::int8_t>();
  const double qx = in.ConsumeIntegral<std::int8_t>();
  const double qy = in.ConsumeIntegral<std::int8_t>();
  const double qz = in.ConsumeIntegral<std::int8_t>();
  Quat q(qw, qx, qy, qz);
  if (q.norm() < 0.5) q = Quat::Identity();
  q.normalize();
  Vec3 t;
  for (int k = 0; k < 3; ++k) t[k] = in.ConsumeIntegral<std::int16_t>() / 16384.0;

  Placed A, B;
  B.place(b.shape, Vec3::Zero(), Mat3::Identity());
  A.place(a.shape, t, q.toRotationMatrix());
  if ((flags & 2) != 0 && t.norm() > 1e-3) {
    const Vec3 n = t.normalized();
    const double g = in.ConsumeIntegral<std::int16_t>() / 1048576.0;  // |g| < 0.032
    const double s = test::oracle_separation(A.body.poly, B.body.poly, n);
    A.place(a.shape, t + (g - s) * n, q.toRotationMatrix());
  }

  const double L = 1.0 + std::max(a.shape.bounding_radius, b.shape.bounding_radius);
  const double tol = 1e-7 * L;
  const double band = cp_detail::kBand * std::min(a.shape.bounding_radius, b.shape.bounding_radius);
  const test::OracleResult o = test::oracle_common_plane(A.body.poly, B.body.poly);

  CommonPlaneCache cache;
  ContactManifold m;
  collide_pair(A.body, B.body, kMargin, cache, m);
  check(o, m, tol, band);
  if ((flags & 4) != 0) {
    ContactManifold warm;
    collide_pair(A.body, B.body, kMargin, cache, warm);
    check(o, warm, tol, band);
  }
  return 0;
}

#include "ratchet/contact/manifold_reuse.hpp"

#include <cmath>

namespace ratchet {

PairPose pair_pose(const PolyhedronView& a, const PolyhedronView& b) {
  PairPose p;
  p.rotation = a.R.transpose() * b.R;
  p.offset = a.R.transpose() * (b.center - a.center);
  p.scale_a = a.scale;
  p.scale_b = b.scale;
  return p;
}

// B's point o + s_B R u moves by (o - o0) + (R - R0) s_B u + R0 (s_B - s_B0) u, A's point
// s_A v by (s_A - s_A0) v; the Frobenius norm bounds the spectral norm of R - R0.
double pair_motion(const PairPose& then, const PairPose& now, double radius_a, double radius_b) {
  return (now.offset - then.offset).norm() + (now.rotation - then.rotation).norm() * now.scale_b * radius_b +
         std::abs(now.scale_b - then.scale_b) * radius_b + std::abs(now.scale_a - then.scale_a) * radius_a;
}

KeptManifold keep_manifold(int ia, int ib, const PolyhedronView& a, const PolyhedronView& b,
                           const ContactManifold& m, double gap_bound, bool normal_on_b) {
  KeptManifold k;
  k.a = ia;
  k.b = ib;
  k.pose = pair_pose(a, b);
  k.gap_bound = gap_bound;
  k.count = m.count;
  k.normal_on_b = normal_on_b;
  if (m.count == 0) return k;
  const Vec3& n = m.points[0].normal;  // one normal per manifold (the common plane's)
  k.normal = (normal_on_b ? b.R : a.R).transpose() * n;
  for (int c = 0; c < m.count; ++c) {
    const ContactPoint& p = m.points[static_cast<std::size_t>(c)];
    const Vec3 xa = p.point + p.normal * (0.5 * p.gap);  // A's surface point
    const Vec3 xb = p.point - p.normal * (0.5 * p.gap);  // B's
    k.on_a[static_cast<std::size_t>(c)] = a.R.transpose() * (xa - a.center) / a.scale;
    k.on_b[static_cast<std::size_t>(c)] = b.R.transpose() * (xb - b.center) / b.scale;
    k.feature_a[static_cast<std::size_t>(c)] = p.feature_a;
    k.feature_b[static_cast<std::size_t>(c)] = p.feature_b;
  }
  return k;
}

void replay_manifold(const KeptManifold& k, const PolyhedronView& a, const PolyhedronView& b, ContactManifold& out) {
  out.count = 0;
  if (k.count == 0) return;
  const Vec3 n = (k.normal_on_b ? b.R : a.R) * k.normal;
  for (int c = 0; c < k.count; ++c) {
    const Vec3 xa = a.center + a.scale * (a.R * k.on_a[static_cast<std::size_t>(c)]);
    const Vec3 xb = b.center + b.scale * (b.R * k.on_b[static_cast<std::size_t>(c)]);
    ContactPoint p;
    p.normal = n;
    p.gap = n.dot(xa - xb);
    p.point = 0.5 * (xa + xb);
    p.feature_a = k.feature_a[static_cast<std::size_t>(c)];
    p.feature_b = k.feature_b[static_cast<std::size_t>(c)];
    out.add(p);
  }
}

}  // namespace ratchet

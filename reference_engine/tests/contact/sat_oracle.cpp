#include "sat_oracle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ratchet/contact/narrow_phase.hpp"  // closest_point_on_triangle (its own unit test: narrow_phase_test)

namespace ratchet::test {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

int count(const PolyhedronView& p) { return static_cast<int>(p.shape->vertices.size()); }

void extent(const PolyhedronView& p, const Vec3& n, double& lo, double& hi) {
  lo = kInf;
  hi = -kInf;
  for (int i = 0; i < count(p); ++i) {
    const double x = n.dot(p.world_vertices[i]);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
}

// Ericson 2005, s. 5.1.9 (ClosestPtSegmentSegment): closest points c1 on p1q1, c2 on p2q2.
void closest_segment_segment(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Vec3& c1,
                             Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2);
  const double denom = a * e - b * b;
  double s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
}

// Shortest link between the separated bodies, as a - b.
Vec3 brute_force_link(const PolyhedronView& a, const PolyhedronView& b) {
  Vec3 best = Vec3::Zero();
  double best_d2 = kInf;
  auto offer = [&](const Vec3& link) {
    const double d2 = link.squaredNorm();
    if (d2 < best_d2) { best_d2 = d2; best = link; }
  };
  auto vertex_faces = [&](const PolyhedronView& p, const PolyhedronView& q, double sign) {
    for (int i = 0; i < count(p); ++i) {
      const Vec3& x = p.world_vertices[i];
      for (const auto& face : q.shape->faces) {
        const Vec3& v0 = q.world_vertices[face[0]];
        for (std::size_t k = 1; k + 1 < face.size(); ++k) {
          const Vec3 y = closest_point_on_triangle(x, v0, q.world_vertices[face[k]], q.world_vertices[face[k + 1]]);
          offer(sign * (x - y));
        }
      }
    }
  };
  vertex_faces(a, b, 1.0);
  vertex_faces(b, a, -1.0);
  for (const auto& ea : a.shape->edges)
    for (const auto& eb : b.shape->edges) {
      Vec3 ca, cb;
      closest_segment_segment(a.world_vertices[ea[0]], a.world_vertices[ea[1]], b.world_vertices[eb[0]],
                              b.world_vertices[eb[1]], ca, cb);
      offer(ca - cb);
    }
  return best;
}

}  // namespace

double oracle_separation(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n) {
  double alo, ahi, blo, bhi;
  extent(a, n, alo, ahi);
  extent(b, n, blo, bhi);
  return alo - bhi;
}

OracleResult oracle_common_plane(const PolyhedronView& a, const PolyhedronView& b, double tie_angle) {
  struct Axis {
    Vec3 n;
    double s;
  };
  thread_local std::vector<Axis> axes;
  axes.clear();
  auto both_signs = [&](const Vec3& n) {
    double alo, ahi, blo, bhi;
    extent(a, n, alo, ahi);
    extent(b, n, blo, bhi);
    axes.push_back({n, alo - bhi});
    axes.push_back({-n, blo - ahi});
  };
  for (std::size_t f = 0; f < a.shape->faces.size(); ++f) both_signs(a.face_normal(static_cast<int>(f)));
  for (std::size_t g = 0; g < b.shape->faces.size(); ++g) both_signs(b.face_normal(static_cast<int>(g)));
  for (const auto& ea : a.shape->edges) {
    const Vec3 u = a.world_vertices[ea[1]] - a.world_vertices[ea[0]];
    for (const auto& eb : b.shape->edges) {
      const Vec3 v = b.world_vertices[eb[1]] - b.world_vertices[eb[0]];
      const Vec3 c = u.cross(v);
      // Exactly parallel edges span no facet; any other pair is a valid axis (every
      // direction gives a lower bound), so no threshold is needed beyond zero length.
      if (c.squaredNorm() > 0.0) both_signs(c.normalized());
    }
  }
  OracleResult r;
  const Axis* best = &axes.front();
  for (const Axis& ax : axes)
    if (ax.s > best->s) best = &ax;
  r.sat_gap = best->s;
  r.normal = best->n;
  r.gap = best->s;
  r.runner_up = -kInf;
  const double cos_tie = std::cos(tie_angle);
  for (const Axis& ax : axes)
    if (ax.n.dot(best->n) < cos_tie) r.runner_up = std::max(r.runner_up, ax.s);
  r.separated = best->s > 0.0;
  if (r.separated) {
    const Vec3 link = brute_force_link(a, b);
    r.gap = link.norm();
    r.normal = link / r.gap;
  }
  return r;
}

}  // namespace ratchet::test

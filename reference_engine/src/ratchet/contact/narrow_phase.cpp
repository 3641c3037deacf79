#include "ratchet/contact/narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ratchet/contact/manifold_reduction.hpp"

namespace ratchet {

namespace {

// A vertex within kPlaneBand r of the lowest one touches the plane (the contact band of
// the Common Plane manifold, common_plane_region.cpp: a face tilted by less than ~1e-3 rad
// still lies on the plane); farther vertices within the margin are about to close.
constexpr double kPlaneBand = 1e-3;

}  // namespace

bool collide_sphere_sphere(const Vec3& ca, double ra, const Vec3& cb, double rb, double margin,
                           ContactManifold& out) {
  out.count = 0;
  const Vec3 d = ca - cb;
  const double dist = d.norm();
  const double g = dist - ra - rb;
  if (g > margin) return false;
  // Coincident centres: any direction is a valid normal; take +z deterministically.
  const Vec3 n = dist > 0.0 ? Vec3(d / dist) : Vec3::UnitZ();
  ContactPoint c;
  c.normal = n;
  c.gap = g;
  c.point = cb + n * (rb + 0.5 * g);  // midway between the two surfaces
  out.add(c);
  return true;
}

bool collide_sphere_plane(const Vec3& c, double r, const Vec3& n, const Vec3& p, double margin,
                          ContactManifold& out) {
  out.count = 0;
  const double dist = n.dot(c - p);
  const double g = dist - r;
  if (g > margin) return false;
  ContactPoint cp;
  cp.normal = n;
  cp.gap = g;
  cp.point = c - n * (r + 0.5 * g);
  out.add(cp);
  return true;
}

bool collide_polyhedron_plane(const PolyhedronView& a, const Vec3& n, const Vec3& p, double margin,
                              ContactManifold& out) {
  out.count = 0;
  // Cheap reject: the whole body lies beyond the margin.
  if (n.dot(a.center - p) - a.scale * a.shape->bounding_radius > margin) return false;
  thread_local std::vector<ContactPoint> candidates;
  candidates.clear();
  const int nv = static_cast<int>(a.shape->vertices.size());
  for (int i = 0; i < nv; ++i) {
    const Vec3& v = a.world_vertices[i];
    const double g = n.dot(v - p);
    if (g > margin) continue;
    ContactPoint c;
    c.normal = n;
    c.gap = g;
    c.point = v - n * (0.5 * g);
    c.feature_a = feature_id(FeatureKind::Vertex, i);
    c.feature_b = 0;
    candidates.push_back(c);
  }
  // The support polygon is made of the touching vertices: a body resting on an edge
  // lost one of its two floor vertices every other step and rocked when all candidates
  // were reduced together (a settled bed of 2000, docs/performance.md).
  double g_min = std::numeric_limits<double>::infinity();
  for (const ContactPoint& c : candidates) g_min = std::min(g_min, c.gap);
  reduce_touching_first(candidates, g_min + kPlaneBand * a.scale * a.shape->bounding_radius, out);
  return out.count > 0;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

bool collide_sphere_polyhedron(const Vec3& c, double r, const PolyhedronView& b, double margin,
                               ContactManifold& out) {
  out.count = 0;
  if ((c - b.center).norm() - r - b.scale * b.shape->bounding_radius > margin) return false;
  const ConvexPolyhedron& shape = *b.shape;
  const int nf = static_cast<int>(shape.faces.size());
  // Signed distance of the centre to every face plane: inside iff all are negative.
  int best_face = 0;
  double best_sd = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < nf; ++f) {
    const double sd = b.face_normal(f).dot(c) - b.face_offset(f);
    if (sd > best_sd) { best_sd = sd; best_face = f; }
  }
  ContactPoint cp;
  if (best_sd <= 0.0) {
    // Centre inside B: push out through the face of least penetration.
    const Vec3 n = b.face_normal(best_face);
    cp.normal = n;
    cp.gap = best_sd - r;
    cp.point = c - n * (r + 0.5 * cp.gap);
    cp.feature_b = feature_id(FeatureKind::Face, best_face);
  } else {
    double best_d2 = std::numeric_limits<double>::infinity();
    Vec3 best_q = Vec3::Zero();
    for (int f = 0; f < nf; ++f) {
      const std::vector<int>& face = shape.faces[static_cast<std::size_t>(f)];
      if (b.face_normal(f).dot(c) - b.face_offset(f) <= 0.0) continue;  // back face
      const Vec3& v0 = b.world_vertices[face[0]];
      for (std::size_t k = 1; k + 1 < face.size(); ++k) {
        const Vec3 q = closest_point_on_triangle(c, v0, b.world_vertices[face[k]], b.world_vertices[face[k + 1]]);
        const double d2 = (c - q).squaredNorm();
        if (d2 < best_d2) { best_d2 = d2; best_q = q; best_face = f; }
      }
    }
    const double dist = std::sqrt(best_d2);
    cp.gap = dist - r;
    if (cp.gap > margin) return false;
    cp.normal = (c - best_q) / dist;
    cp.point = best_q + cp.normal * (0.5 * cp.gap);
    cp.feature_b = feature_id(FeatureKind::Face, best_face);
  }
  if (cp.gap > margin) return false;
  cp.feature_a = 0;
  out.add(cp);
  return true;
}

}  // namespace ratchet

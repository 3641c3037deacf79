// GJK on D = A - B (Gilbert, Johnson & Keerthi 1988; closest points on the simplex by
// Voronoi regions, Ericson 2005, s. 5.1.2-5.1.6). v is the point of the current simplex
// closest to the origin; its direction is the normal from B towards A. Used when the
// bodies are apart (or were apart last step); common_plane.hpp gives the method.
#include <algorithm>
#include <array>
#include <cmath>

#include "ratchet/contact/common_plane_detail.hpp"

namespace ratchet::cp_detail {

namespace {

Vec3 closest_on_segment(Simplex& s) {
  const Vec3 a = s.v[0].w, b = s.v[1].w, ab = b - a;
  const double t = -a.dot(ab);
  if (t <= 0.0) { s.n = 1; return a; }
  const double dd = ab.squaredNorm();
  if (t >= dd) { s.v[0] = s.v[1]; s.n = 1; return b; }
  return a + ab * (t / dd);
}

void keep(Simplex& s, int i) { s.v[0] = s.v[static_cast<std::size_t>(i)]; s.n = 1; }
void keep(Simplex& s, int i, int j) {
  const SimplexVertex vi = s.v[static_cast<std::size_t>(i)], vj = s.v[static_cast<std::size_t>(j)];
  s.v[0] = vi;
  s.v[1] = vj;
  s.n = 2;
}

// Ericson 2005, ClosestPtPointTriangle (s. 5.1.5) with p = origin. In the face region
// the point is the projection n (n.a)/(n.n): its direction comes from the cross product
// and does not suffer from the barycentric cancellation.
Vec3 closest_on_triangle(Simplex& s) {
  const Vec3 a = s.v[0].w, b = s.v[1].w, c = s.v[2].w;
  const Vec3 ab = b - a, ac = c - a;
  const double d1 = -ab.dot(a), d2 = -ac.dot(a);
  if (d1 <= 0.0 && d2 <= 0.0) { keep(s, 0); return a; }
  const double d3 = -ab.dot(b), d4 = -ac.dot(b);
  if (d3 >= 0.0 && d4 <= d3) { keep(s, 1); return b; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    keep(s, 0, 1);
    return a + ab * (d1 / (d1 - d3));
  }
  const double d5 = -ab.dot(c), d6 = -ac.dot(c);
  if (d6 >= 0.0 && d5 <= d6) { keep(s, 2); return c; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    keep(s, 0, 2);
    return a + ac * (d2 / (d2 - d6));
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    keep(s, 1, 2);
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const Vec3 nrm = ab.cross(ac);
  const double nn = nrm.squaredNorm();
  if (nn > kDegenerateSin2 * ab.squaredNorm() * ac.squaredNorm()) return nrm * (nrm.dot(a) / nn);
  // Degenerate (collinear) triangle that rounding put in the face region: best edge.
  Simplex best;
  Vec3 best_v = Vec3::Zero();
  double best_d = kInf;
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (const auto& p : pairs) {
    Simplex e;
    e.v[0] = s.v[static_cast<std::size_t>(p[0])];
    e.v[1] = s.v[static_cast<std::size_t>(p[1])];
    e.n = 2;
    const Vec3 v = closest_on_segment(e);
    if (v.squaredNorm() < best_d) { best_d = v.squaredNorm(); best_v = v; best = e; }
  }
  s = best;
  return best_v;
}

// Ericson 2005, ClosestPtPointTetrahedron (s. 5.1.6): the closest point over the faces
// whose plane separates the origin from the opposite vertex; none means inside.
Vec3 closest_on_tetrahedron(Simplex& s, bool& inside) {
  static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  const Vec3& p0 = s.v[0].w;
  const Vec3 e1 = s.v[1].w - p0, e2 = s.v[2].w - p0, e3 = s.v[3].w - p0;
  const double det = e1.cross(e2).dot(e3);
  const bool degenerate = std::abs(det) <= kDegenerateVolume * e1.norm() * e2.norm() * e3.norm();
  Simplex best;
  Vec3 best_v = Vec3::Zero();
  double best_d = kInf;
  bool any = false;
  for (const auto& f : kFaces) {
    const Vec3& a = s.v[static_cast<std::size_t>(f[0])].w;
    const Vec3 nrm = (s.v[static_cast<std::size_t>(f[1])].w - a).cross(s.v[static_cast<std::size_t>(f[2])].w - a);
    const double side_origin = -nrm.dot(a);
    const double side_vertex = nrm.dot(s.v[static_cast<std::size_t>(f[3])].w - a);
    if (!degenerate && side_origin * side_vertex > 0.0) continue;  // origin on the inner side
    any = true;
    Simplex t;
    for (int k = 0; k < 3; ++k) t.v[static_cast<std::size_t>(k)] = s.v[static_cast<std::size_t>(f[k])];
    t.n = 3;
    const Vec3 v = closest_on_triangle(t);
    if (v.squaredNorm() < best_d) { best_d = v.squaredNorm(); best_v = v; best = t; }
  }
  inside = !any;
  if (any) s = best;
  return best_v;
}

Vec3 closest_on_simplex(Simplex& s, bool& inside) {
  inside = false;
  switch (s.n) {
    case 1: return s.v[0].w;
    case 2: return closest_on_segment(s);
    case 3: return closest_on_triangle(s);
    default: return closest_on_tetrahedron(s, inside);
  }
}

}  // namespace

GjkOutcome gjk(const PolyhedronView& a, const PolyhedronView& b, Simplex s, double cutoff) {
  GjkOutcome out;
  const double touch = kGjkTouch * pair_length(a, b);
  bool inside = false;
  Vec3 v = closest_on_simplex(s, inside);
  bool converged = false;
  for (int it = 0; it < kGjkMaxIterations && !inside; ++it) {
    const double nv = v.norm();
    if (!(nv > touch)) break;  // touching to rounding: no direction
    const Vec3 n = v / nv;
    // Support of D in direction -n: the pair that touches the plane with normal n.
    const AxisValue av = evaluate_axis(a, b, n);
    ++out.iterations;
    if (av.s > out.s) { out.s = av.s; out.n = n; }
    if (out.s > cutoff) { out.early_out = true; break; }
    // |v| is an upper bound of the distance, s(n) a lower bound (van den Bergen 1999).
    if (nv - av.s <= kGjkRelative * nv) { converged = true; break; }
    bool known = false;
    for (int k = 0; k < s.n; ++k)
      known = known || (s.v[static_cast<std::size_t>(k)].ia == av.ia && s.v[static_cast<std::size_t>(k)].ib == av.ib);
    if (known) { converged = true; break; }  // no new vertex: v is final
    const Simplex previous = s;
    SimplexVertex& nw = s.v[static_cast<std::size_t>(s.n++)];
    nw.ia = av.ia;
    nw.ib = av.ib;
    nw.w = a.world_vertices[av.ia] - b.world_vertices[av.ib];
    const Vec3 v_new = closest_on_simplex(s, inside);
    if (!inside && !(v_new.squaredNorm() < v.squaredNorm())) {
      s = previous;  // rounding floor reached: |v| no longer decreases
      converged = true;
      break;
    }
    v = v_new;
  }
  out.simplex = s;
  out.v = v;
  out.proven_apart = converged && !inside && out.s > 0.0;
  return out;
}

// GJK's v carries an absolute rounding error ~1e-16 of the coordinates, so for a tiny
// distance its direction is off to first order. The closest features are known exactly
// though (the distinct vertices of A and of B in the final simplex): the true normal is
// orthogonal to their edge directions. Remove those components from v; for a face or
// two crossing edges this is the exact cross-product normal.
bool polish_normal(const PolyhedronView& a, const PolyhedronView& b, const Simplex& s, const Vec3& n,
                   Vec3& out) {
  std::array<int, 4> ia{}, ib{};
  int na = 0, nb = 0;
  for (int k = 0; k < s.n; ++k) {
    const SimplexVertex& sv = s.v[static_cast<std::size_t>(k)];
    if (std::find(ia.begin(), ia.begin() + na, sv.ia) == ia.begin() + na) ia[static_cast<std::size_t>(na++)] = sv.ia;
    if (std::find(ib.begin(), ib.begin() + nb, sv.ib) == ib.begin() + nb) ib[static_cast<std::size_t>(nb++)] = sv.ib;
  }
  std::array<Vec3, 3> basis;
  int nq = 0;
  auto add = [&](const Vec3& d) {
    if (nq == 3) return;
    Vec3 r = d;
    for (int q = 0; q < nq; ++q) r -= basis[static_cast<std::size_t>(q)] * basis[static_cast<std::size_t>(q)].dot(r);
    const double len = r.norm();
    if (len > kSpanRelative * d.norm()) basis[static_cast<std::size_t>(nq++)] = r / len;
  };
  for (int k = 1; k < na; ++k) add(a.world_vertices[ia[static_cast<std::size_t>(k)]] - a.world_vertices[ia[0]]);
  for (int k = 1; k < nb; ++k) add(b.world_vertices[ib[static_cast<std::size_t>(k)]] - b.world_vertices[ib[0]]);
  if (nq == 0 || nq == 3) return false;
  Vec3 p = n;
  for (int q = 0; q < nq; ++q) p -= basis[static_cast<std::size_t>(q)] * basis[static_cast<std::size_t>(q)].dot(p);
  const double len = p.norm();
  if (!(len > 0.5)) return false;  // v not near-orthogonal to the features: not the final simplex
  out = p / len;
  return true;
}

}  // namespace ratchet::cp_detail

// Facet search for overlapping (or touching) bodies: the SAT over the facets of D with
// pruning (Gregorius 2013 for the Gauss-map test). The certificate's far scan
// (common_plane_certificate.cpp) reuses these bounds.
//
// Every axis is first bounded from above; only axes whose bound beats the best value
// s* found so far are evaluated. Two bounds, both rigorous for every unit n:
//  (1) centres: with a = c_A + a', b = c_B + b' and d = c_A - c_B,
//        s(n) = n.d - h_A'(-n) - h_B'(n) <= n.d - rho_A - rho_B,
//      rho = inradius about the centre of mass (the ball of radius rho lies inside, so
//      every support function is at least rho);
//  (2) contact vertices: for any a* in A and b* in B, s(n) <= n.(a* - b*). For the face
//      axis of face g of B this is the signed distance of a* from g's plane,
//      m_g.a* - d_g (and m_f.b* - d_f for a face f of A); the minimum over several a*
//      (b*) is a bound too. For n on the Gauss arc of an edge of A, min_a n.a = n.P (P
//      on the edge), so s(n) <= n.(P - b*), a linear function of n whose values at the
//      arc's ends are the bounds (2) of the edge's two faces; likewise for edges of B.
//      The reference vertices are the kRefVertices best supports of each body along the
//      best axis so far: the corners of its contact feature, which lie on both sides of
//      every plane through the contact that is not the contact plane itself.
// A linear function w.c on the arc between unit p and q is at most M / cos(theta/2)
// if M = max(p.c, q.c) > 0, else at most M (theta the arc length: w = (alpha p +
// beta q)/|alpha p + beta q| and |alpha p + beta q| >= (alpha + beta) cos(theta/2)).
// Bound (2) keeps only the features within |s*| of the contact: a warm start, whose
// s* is near the optimum from the outset, evaluates a handful of axes; bound (1) helps
// when the bodies are far apart or the start axis is poor.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "ratchet/contact/common_plane_detail.hpp"

namespace ratchet::cp_detail {

namespace {

// Upper bound over the arc between unit p and q of a linear function with end values
// m_p, m_q; cos_theta = p.q.
bool arc_may_exceed(double m_p, double m_q, double cos_theta, double target) {
  const double m = std::max(m_p, m_q);
  if (m > target) return true;
  if (m <= 0.0) return false;  // the arc's bound is m itself
  // 0 < m <= target: m / cos(theta/2) > target  <=>  2 m^2 > target^2 (1 + cos theta)
  return 2.0 * m * m > target * target * (1.0 + cos_theta);
}

}  // namespace

int top_supports(const PolyhedronView& q, const Vec3& u, std::array<int, kRefVertices>& idx) {
  std::array<double, kRefVertices> h{};
  int k = 0;
  for (int i = 0; i < vertex_count(q); ++i) {
    const double x = u.dot(q.world_vertices[i]);
    if (k < kRefVertices) {
      ++k;
    } else if (!(x > h[kRefVertices - 1])) {
      continue;
    }
    int j = k - 1;  // insertion into the sorted list
    while (j > 0 && h[static_cast<std::size_t>(j - 1)] < x) {
      h[static_cast<std::size_t>(j)] = h[static_cast<std::size_t>(j - 1)];
      idx[static_cast<std::size_t>(j)] = idx[static_cast<std::size_t>(j - 1)];
      --j;
    }
    h[static_cast<std::size_t>(j)] = x;
    idx[static_cast<std::size_t>(j)] = i;
  }
  return k;
}

// Prepares the bounds of body p's face axes (sign: n = sign * outward normal) with the
// other body's reference vertices `refs`, and the faces that may beat lim.
void face_bounds(const PolyhedronView& p, double sign, const Vec3& d, const PolyhedronView& other,
                 const std::array<int, kRefVertices>& refs, int nrefs, double rho, double lim,
                 SideBounds& out) {
  const ConvexPolyhedron& P = *p.shape;
  const std::size_t nf = P.faces.size();
  const Mat3 Rt = p.R.transpose();
  const Vec3 d_body = Rt * d;
  out.shape = &P;
  out.scale = p.scale;
  out.refs = nrefs;
  for (int k = 0; k < nrefs; ++k)
    out.x_body[static_cast<std::size_t>(k)] = Rt * (other.world_vertices[refs[static_cast<std::size_t>(k)]] - p.center) / p.scale;
  out.centre.resize(nf);
  out.vertex.resize(nf);
  out.done.assign(nf, 1);
  out.hot.resize(nf);
  out.candidates.clear();
  // Bound (1) and the first reference value of every face (the rest on demand); plain
  // scalar loop over the contiguous normals (the hot path of a warm start).
  const Vec3 sd = sign * d_body;
  const Vec3 x0 = out.x_body[0];
  const double hot = std::min(lim, 0.0), scale = p.scale;
  const double* m = P.face_normals.front().data();  // std::vector<Vec3>: 3 doubles each
  const double* off = P.face_offsets.data();
  double* centre = out.centre.data();
  unsigned char* hot_flag = out.hot.data();
  for (std::size_t f = 0; f < nf; ++f, m += 3) {
    const double c = m[0] * sd.x() + m[1] * sd.y() + m[2] * sd.z();
    const double v0 = scale * (m[0] * x0.x() + m[1] * x0.y() + m[2] * x0.z() - off[f]);
    centre[f] = c;
    out.vertex[f][0] = v0;
    hot_flag[f] = v0 > hot;
    if (v0 > lim && c - rho > lim) out.candidates.push_back(static_cast<int>(f));
  }
}

// Edges of body p whose Gauss arc may hold an axis better than lim (both bounds; bound
// (2) per reference vertex, each valid along the whole arc).
void active_edges(const PolyhedronView& p, SideBounds& bounds, double rho, double lim,
                  std::vector<EdgeData>& out) {
  const ConvexPolyhedron& P = *p.shape;
  out.clear();
  // Necessary for bound (2) with the first reference vertex to pass: one end value
  // above min(lim, 0) (if both are <= lim and <= 0, the arc's bound is their maximum).
  // The flags were set with an earlier, lower lim: a superset, so still safe.
  const unsigned char* hot = bounds.hot.data();
  const std::size_t ne = P.edges.size();
  const int* faces_of_edge = P.edge_faces.front().data();  // std::array<int, 2> each
  for (std::size_t e = 0; e < ne; ++e) {
    const int f1 = faces_of_edge[2 * e], f2 = faces_of_edge[2 * e + 1];
    if (!(hot[f1] | hot[f2])) continue;
    const double cos_theta = P.face_normals[static_cast<std::size_t>(f1)].dot(P.face_normals[static_cast<std::size_t>(f2)]);
    if (!arc_may_exceed(bounds.centre[static_cast<std::size_t>(f1)], bounds.centre[static_cast<std::size_t>(f2)],
                        cos_theta, lim + rho))
      continue;
    bool may = true;
    for (int k = 0; k < bounds.refs && may; ++k)
      may = arc_may_exceed(bounds.value(f1, k), bounds.value(f2, k), cos_theta, lim);
    if (!may) continue;
    out.push_back(edge_data(p, static_cast<int>(e)));
  }
}

// Raises `best` to the best facet of D (every facet that could beat it is evaluated);
// `best_face` receives the best face axis seen. Returns early once best.s > cutoff.
void sat_search(const PolyhedronView& a, const PolyhedronView& b, Candidate& best, Candidate& best_face,
                double cutoff, CommonPlaneResult& r) {
  thread_local SatScratch sc;
  const Vec3 d = a.center - b.center;
  const double rho = inradius(a) + inradius(b);
  const double safety = kPruneSafety * pair_length(a, b);

  // Reference vertices along the best axis so far, and the bounds of every face axis.
  auto bound_faces = [&] {
    std::array<int, kRefVertices> ref_a{}, ref_b{};
    const int na = top_supports(a, -best.n, ref_a);  // A's lowest along n
    const int nb = top_supports(b, best.n, ref_b);   // B's highest along n
    face_bounds(a, -1.0, d, b, ref_b, nb, rho, best.s - safety, sc.a);  // A's face axes: n = -m
    face_bounds(b, +1.0, d, a, ref_a, na, rho, best.s - safety, sc.b);
  };
  bound_faces();

  const double s_start = best.s;
  for (const int f : sc.a.candidates) {
    if (!face_may_win(sc.a, f, rho, best.s - safety)) continue;
    if (best.kind == PlaneFeature::FaceA && best.index_a == f) continue;  // the start axis
    Vec3 n;
    const double s = face_a_value(a, b, f, n);
    ++r.sat_axes;
    offer(best, s, n, PlaneFeature::FaceA, f, -1);
    offer(best_face, s, n, PlaneFeature::FaceA, f, -1);
    if (best.s > cutoff) return;
  }
  for (const int g : sc.b.candidates) {
    if (!face_may_win(sc.b, g, rho, best.s - safety)) continue;
    if (best.kind == PlaneFeature::FaceB && best.index_b == g) continue;
    Vec3 n;
    const double s = face_b_value(a, b, g, n);
    ++r.sat_axes;
    offer(best, s, n, PlaneFeature::FaceB, -1, g);
    offer(best_face, s, n, PlaneFeature::FaceB, -1, g);
    if (best.s > cutoff) return;
  }
  // A markedly better face axis has better contact vertices: tighter bounds for the
  // edges (any vertices give valid bounds, so a marginal change is not worth it).
  if (best.s > s_start + kRebound * pair_length(a, b)) bound_faces();

  const double lim = best.s - safety;
  active_edges(a, sc.a, rho, lim, sc.ea);
  if (sc.ea.empty()) return;
  active_edges(b, sc.b, rho, lim, sc.eb);

  const bool start_pair = best.kind == PlaneFeature::EdgeEdge;
  const int start_a = best.index_a, start_b = best.index_b;
  for (const EdgeData& ea : sc.ea) {
    for (const EdgeData& eb : sc.eb) {
      if (start_pair && ea.e == start_a && eb.e == start_b) continue;  // the start axis
      ++r.sat_edge_pairs;
      double s = 0.0;
      Vec3 n;
      if (!edge_pair_facet(ea, eb, s, n)) continue;
      ++r.sat_axes;
      offer(best, s, n, PlaneFeature::EdgeEdge, ea.e, eb.e);
      if (best.s > cutoff) return;
    }
  }
}

}  // namespace ratchet::cp_detail

// Contact region of a pair whose common plane is known (docs/method.md section 3): the
// band features of each body, projected on the plane, clipped (Sutherland & Hodgman 1974,
// "Reentrant polygon clipping", CACM 17(1); Cyrus & Beck 1978 for a segment), lifted
// back onto both surfaces, and reduced to at most 4 points. Each region case is one
// function below, chosen by the sizes of the two band features' hulls.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "ratchet/contact/common_plane_detail.hpp"
#include "ratchet/contact/manifold_reduction.hpp"

namespace ratchet::cp_detail {

namespace {

struct Pt2 {
  double x = 0.0, y = 0.0;
};
double cross2(const Pt2& o, const Pt2& p, const Pt2& q) {
  return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
}
// Distance in the plane (coordinates are O(10): no overflow, so no hypot).
double dist2(const Pt2& p, const Pt2& q) { return std::sqrt((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y)); }

// A point of the contact region with its provenance.
struct RegionPoint {
  Pt2 p;
  int va = -1, vb = -1;  // vertex of A / B if the point is that vertex (exact height)
  std::int32_t fa = 0, fb = 0;
  int label = 0;  // clipping: the polygon edge leaving this point, >= 0 A hull edge, < 0 B hull edge (-1-l)
};

struct SideFace {
  Vec3 m;
  double d;
  double mn;  // m.n
};

struct ManifoldScratch {
  std::vector<int> band_a, band_b;
  std::vector<Pt2> pa, pb;          // projected band vertices
  std::vector<int> order, hull_a, hull_b;  // hull: indices into band lists, CCW
  std::vector<RegionPoint> poly, next;
  std::vector<SideFace> faces_a, faces_b;
  std::vector<int> face_list;
  std::vector<std::uint64_t> face_bits;
  std::vector<double> height_a, height_b;  // n.x of every vertex
  std::vector<ContactPoint> candidates;
};

// Andrew's monotone chain (Andrew 1979, IPL 9(5)): CCW hull of pts, collinear points
// (within eps in doubled area) dropped. Writes indices into `hull`.
void hull_2d(const std::vector<Pt2>& pts, double eps, std::vector<int>& order, std::vector<int>& hull) {
  const int n = static_cast<int>(pts.size());
  auto before = [&](int i, int j) {
    const Pt2& p = pts[static_cast<std::size_t>(i)];
    const Pt2& q = pts[static_cast<std::size_t>(j)];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return i < j;
  };
  // One or two band vertices (a vertex or an edge, the common case): the chain below
  // would return them in sorted order.
  if (n <= 2) {
    hull.resize(static_cast<std::size_t>(n));
    if (n >= 1) hull[0] = 0;
    if (n == 2) {
      const bool swap = before(1, 0);
      hull[0] = swap ? 1 : 0;
      hull[1] = swap ? 0 : 1;
    }
    return;
  }
  order.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), before);
  hull.assign(static_cast<std::size_t>(2 * n + 1), 0);
  int k = 0;
  auto at = [&](int h) -> const Pt2& { return pts[static_cast<std::size_t>(hull[static_cast<std::size_t>(h)])]; };
  for (int i = 0; i < n; ++i) {
    const int o = order[static_cast<std::size_t>(i)];
    while (k >= 2 && cross2(at(k - 2), at(k - 1), pts[static_cast<std::size_t>(o)]) <= eps) --k;
    hull[static_cast<std::size_t>(k++)] = o;
  }
  for (int i = n - 2, t = k + 1; i >= 0; --i) {
    const int o = order[static_cast<std::size_t>(i)];
    while (k >= t && cross2(at(k - 2), at(k - 1), pts[static_cast<std::size_t>(o)]) <= eps) --k;
    hull[static_cast<std::size_t>(k++)] = o;
  }
  hull.resize(static_cast<std::size_t>(std::max(1, k - 1)));
}

// Id of the edge of s between vertices i and j; two hull corners of a band that share
// no edge (a diagonal across a face) get `fallback`, the feature that holds both.
std::int32_t edge_or(const ConvexPolyhedron& s, int i, int j, std::int32_t fallback) {
  const std::array<int, 2> key{std::min(i, j), std::max(i, j)};
  const auto it = std::lower_bound(s.edges.begin(), s.edges.end(), key);  // edges are sorted
  if (it != s.edges.end() && *it == key) return feature_id(FeatureKind::Edge, static_cast<int>(it - s.edges.begin()));
  return fallback;
}

// Lower surface of A (faces facing B) / upper surface of B along the line x0 + t n.
double lift_a(const std::vector<SideFace>& faces, const Vec3& x0, double fallback) {
  double t = -kInf;
  for (const SideFace& f : faces) t = std::max(t, (f.d - f.m.dot(x0)) / f.mn);
  return std::max(t, fallback);  // never below the supporting plane (rounding)
}
double lift_b(const std::vector<SideFace>& faces, const Vec3& x0, double fallback) {
  double t = kInf;
  for (const SideFace& f : faces) t = std::min(t, (f.d - f.m.dot(x0)) / f.mn);
  return std::min(t, fallback);
}

// The plane's basis (t1, t2, n), right-handed, from the axis least aligned with n: the
// region is clipped in the 2-D coordinates (t1.x, t2.x).
struct PlaneBasis {
  Vec3 t1, t2;
  Pt2 to2(const Vec3& x) const { return Pt2{t1.dot(x), t2.dot(x)}; }
  Vec3 to3(const Pt2& p) const { return Vec3(t1 * p.x + t2 * p.y); }
};

PlaneBasis plane_basis(const Vec3& n) {
  Eigen::Index k_min = 0;
  n.cwiseAbs().minCoeff(&k_min);
  PlaneBasis basis;
  basis.t1 = Vec3::Unit(k_min).cross(n).normalized();
  basis.t2 = n.cross(basis.t1);
  return basis;
}

// A's lowest vertex along n and B's highest, with their heights n.x.
struct Supports {
  int sa = 0, sb = 0;
  double ha = 0.0, hb = 0.0;
};

// Band features: A's vertices near its lowest plane along n, B's near its highest, with
// their 2-D points. The heights n.x of every vertex are taken once (as argmin_dot /
// argmax_dot compute them), for the supports and the band alike.
Supports band_vertices(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n, double band,
                       const PlaneBasis& basis, ManifoldScratch& sc) {
  const int nva = vertex_count(a), nvb = vertex_count(b);
  sc.height_a.resize(static_cast<std::size_t>(nva));
  sc.height_b.resize(static_cast<std::size_t>(nvb));
  int sa = 0, sb = 0;
  for (int i = 0; i < nva; ++i) {
    sc.height_a[static_cast<std::size_t>(i)] = n.dot(a.world_vertices[i]);
    if (sc.height_a[static_cast<std::size_t>(i)] < sc.height_a[static_cast<std::size_t>(sa)]) sa = i;
  }
  for (int j = 0; j < nvb; ++j) {
    sc.height_b[static_cast<std::size_t>(j)] = n.dot(b.world_vertices[j]);
    if (sc.height_b[static_cast<std::size_t>(j)] > sc.height_b[static_cast<std::size_t>(sb)]) sb = j;
  }
  const double ha = sc.height_a[static_cast<std::size_t>(sa)], hb = sc.height_b[static_cast<std::size_t>(sb)];
  sc.band_a.clear();
  sc.band_b.clear();
  sc.pa.clear();
  sc.pb.clear();
  for (int i = 0; i < nva; ++i)
    if (sc.height_a[static_cast<std::size_t>(i)] <= ha + band) { sc.band_a.push_back(i); sc.pa.push_back(basis.to2(a.world_vertices[i])); }
  for (int j = 0; j < nvb; ++j)
    if (sc.height_b[static_cast<std::size_t>(j)] >= hb - band) { sc.band_b.push_back(j); sc.pb.push_back(basis.to2(b.world_vertices[j])); }
  Supports s;
  s.sa = sa;
  s.sb = sb;
  s.ha = ha;
  s.hb = hb;
  return s;
}

// Faces touching the band of p (they carry the surface over the band region) into
// `faces`; returns the side's reference face (most aligned with the plane). Only faces
// turned towards the other body (sign m.n > kSteep) can carry the surface over the band
// region: the support vertex's normal cone contains sign n, so one of its faces always
// qualifies. The test runs in the body frame (3 multiplications).
int side_faces(const PolyhedronView& p, const std::vector<int>& bandv, double sign, const Vec3& n,
               ManifoldScratch& sc, std::vector<SideFace>& faces) {
  // Faces around the band vertices (vertex_face_list), each once, in ascending order so
  // the reference face is the same whatever the band's order: marked in a bit set, read
  // back word by word (no sort of the list per pair).
  sc.face_bits.assign((p.shape->faces.size() + 63) / 64, 0);
  const int* start = p.shape->vertex_face_start.data();
  const int* list = p.shape->vertex_face_list.data();
  for (int i : bandv)
    for (int k = start[i]; k < start[i + 1]; ++k)
      sc.face_bits[static_cast<std::size_t>(list[k]) >> 6] |= std::uint64_t{1} << (list[k] & 63);
  sc.face_list.clear();
  for (std::size_t w = 0; w < sc.face_bits.size(); ++w)
    for (std::uint64_t bits = sc.face_bits[w]; bits != 0; bits &= bits - 1)
      sc.face_list.push_back(static_cast<int>(64 * w) + __builtin_ctzll(bits));
  const Vec3 n_body = sign * (p.R.transpose() * n);
  faces.clear();
  int ref = -1;
  double ref_mn = -kInf;
  for (int f : sc.face_list) {
    const double facing = p.shape->face_normals[static_cast<std::size_t>(f)].dot(n_body);
    if (!(facing > kSteep)) continue;
    if (facing > ref_mn) { ref_mn = facing; ref = f; }
    const Vec3 m = p.face_normal(f);
    faces.push_back({m, m.dot(p.center) + p.scale * p.shape->face_offsets[static_cast<std::size_t>(f)], m.dot(n)});
  }
  return ref;
}

// A band edge shorter than kSamePoint L is one contact point: its hull becomes a vertex.
void collapse_short_hull(std::vector<int>& h, const std::vector<Pt2>& p, double L) {
  if (h.size() == 2) {
    const Pt2 &p0 = p[static_cast<std::size_t>(h[0])], &p1 = p[static_cast<std::size_t>(h[1])];
    if (dist2(p0, p1) <= kSamePoint * L) h.resize(1);
  }
}

// The hulled band features of both sides, as every region case reads them: hull corner
// h (taken mod the hull size) as a band vertex and a 2-D point, and the ids a region
// point is labelled with (region_*: the whole band feature, a vertex, an edge or the
// reference face).
struct BandHulls {
  const ConvexPolyhedron* A = nullptr;
  const ConvexPolyhedron* B = nullptr;
  const ManifoldScratch* sc = nullptr;
  int ma = 0, mb = 0;  // hull sizes
  std::int32_t region_a = 0, region_b = 0;

  int vert_a(int h) const { return sc->band_a[static_cast<std::size_t>(sc->hull_a[static_cast<std::size_t>(h % ma)])]; }
  int vert_b(int h) const { return sc->band_b[static_cast<std::size_t>(sc->hull_b[static_cast<std::size_t>(h % mb)])]; }
  Pt2 pt_a(int h) const { return sc->pa[static_cast<std::size_t>(sc->hull_a[static_cast<std::size_t>(h % ma)])]; }
  Pt2 pt_b(int h) const { return sc->pb[static_cast<std::size_t>(sc->hull_b[static_cast<std::size_t>(h % mb)])]; }
  // Hull edge from corner h to h + 1; a hull that is one edge is the whole feature.
  std::int32_t edge_a(int h) const { return ma == 2 ? region_a : edge_or(*A, vert_a(h), vert_a(h + 1), region_a); }
  std::int32_t edge_b(int h) const { return mb == 2 ? region_b : edge_or(*B, vert_b(h), vert_b(h + 1), region_b); }
  // Hull corner h as a region point: that vertex (exact height) against the other side's
  // whole feature.
  RegionPoint a_vertex(int h) const {
    RegionPoint q;
    q.p = pt_a(h);
    q.va = vert_a(h);
    q.fa = feature_id(FeatureKind::Vertex, q.va);
    q.fb = region_b;
    return q;
  }
  RegionPoint b_vertex(int h) const {
    RegionPoint q;
    q.p = pt_b(h);
    q.vb = vert_b(h);
    q.fa = region_a;
    q.fb = feature_id(FeatureKind::Vertex, q.vb);
    return q;
  }
};

// Vertex on vertex: one point midway between them in the plane, with both exact heights.
void vertex_on_vertex(const BandHulls& f, std::vector<RegionPoint>& poly) {
  RegionPoint q = f.a_vertex(0);
  const Pt2 pb = f.pt_b(0);
  q.p = {0.5 * (q.p.x + pb.x), 0.5 * (q.p.y + pb.y)};
  q.vb = f.vert_b(0);
  q.fb = feature_id(FeatureKind::Vertex, q.vb);
  poly.push_back(q);
}

// Edge on edge: the crossing point, or the ends of the overlap when (nearly) parallel,
// since such edges touch along a line and one point would let the pair rock.
void edge_on_edge(const BandHulls& f, double eps1, std::vector<RegionPoint>& poly) {
  const Pt2 a0 = f.pt_a(0), a1 = f.pt_a(1), b0 = f.pt_b(0), b1 = f.pt_b(1);
  const double dax = a1.x - a0.x, day = a1.y - a0.y, dbx = b1.x - b0.x, dby = b1.y - b0.y;
  const double la = std::sqrt(dax * dax + day * day), lb = std::sqrt(dbx * dbx + dby * dby);
  const double cr = dax * dby - day * dbx;
  if (std::abs(cr) > kParallelSegmentsSin * la * lb) {
    const double wx = b0.x - a0.x, wy = b0.y - a0.y;
    const double t = std::clamp((wx * dby - wy * dbx) / cr, 0.0, 1.0);
    const double u = std::clamp((wx * day - wy * dax) / cr, 0.0, 1.0);
    RegionPoint q;
    q.p = {0.5 * (a0.x + t * dax + b0.x + u * dbx), 0.5 * (a0.y + t * day + b0.y + u * dby)};
    q.fa = f.region_a;
    q.fb = f.region_b;
    poly.push_back(q);
  } else {
    // Parameters of B's ends along A's segment.
    const double inv = 1.0 / (la * la);
    double tb0 = ((b0.x - a0.x) * dax + (b0.y - a0.y) * day) * inv;
    double tb1 = ((b1.x - a0.x) * dax + (b1.y - a0.y) * day) * inv;
    int hb0 = 0, hb1 = 1;
    if (tb0 > tb1) { std::swap(tb0, tb1); std::swap(hb0, hb1); }
    const RegionPoint lo = tb0 > 0.0 ? f.b_vertex(hb0) : f.a_vertex(0);
    const RegionPoint hi = tb1 < 1.0 ? f.b_vertex(hb1) : f.a_vertex(1);
    if (std::min(tb1, 1.0) >= std::max(tb0, 0.0) - eps1 / la) {
      poly.push_back(lo);
      poly.push_back(hi);
    }
  }
}

// End of a clipped segment s0 -> s1 at parameter t: the segment's own vertex vertex_h
// when no polygon edge cut it there (l < 0), else the crossing with polygon edge l,
// which knows both its features.
RegionPoint segment_end(const BandHulls& f, bool seg_is_a, const Pt2& s0, const Pt2& s1, double t, int l,
                        int vertex_h) {
  if (l < 0) return seg_is_a ? f.a_vertex(vertex_h) : f.b_vertex(vertex_h);
  RegionPoint q;
  q.p = {s0.x + t * (s1.x - s0.x), s0.y + t * (s1.y - s0.y)};
  q.fa = seg_is_a ? f.region_a : f.edge_a(l);
  q.fb = seg_is_a ? f.edge_b(l) : f.region_b;
  return q;
}

// Edge on face: the one side's segment clipped by the other side's polygon (Cyrus &
// Beck 1978, parametric form), which keeps the two ends an edge resting on a face needs.
void segment_in_polygon(const BandHulls& f, double eps1, double eps2, std::vector<RegionPoint>& poly) {
  const bool seg_is_a = f.ma == 2;
  const int m = seg_is_a ? f.mb : f.ma;
  const Pt2 s0 = seg_is_a ? f.pt_a(0) : f.pt_b(0), s1 = seg_is_a ? f.pt_a(1) : f.pt_b(1);
  double t_lo = 0.0, t_hi = 1.0;
  int l_lo = -1, l_hi = -1;
  bool empty = false;
  for (int l = 0; l < m && !empty; ++l) {
    const Pt2 e0 = seg_is_a ? f.pt_b(l) : f.pt_a(l), e1 = seg_is_a ? f.pt_b(l + 1) : f.pt_a(l + 1);
    const double d0 = cross2(e0, e1, s0), d1 = cross2(e0, e1, s1);  // >= 0 inside (CCW)
    if (d0 < -eps2 && d1 < -eps2) { empty = true; break; }
    if (d0 < -eps2) {
      const double t = d0 / (d0 - d1);
      if (t > t_lo) { t_lo = t; l_lo = l; }
    } else if (d1 < -eps2) {
      const double t = d0 / (d0 - d1);
      if (t < t_hi) { t_hi = t; l_hi = l; }
    }
  }
  const double seg_len = dist2(s0, s1);
  if (!empty && t_hi >= t_lo - eps1 / seg_len) {
    poly.push_back(segment_end(f, seg_is_a, s0, s1, t_lo, l_lo, 0));
    poly.push_back(segment_end(f, seg_is_a, s0, s1, t_hi, l_hi, 1));
  }
}

// Where the clipped polygon's edge cur -> nx (signed doubled areas dc, dn against B's
// edge l) crosses B's edge l, leaving with label label_out. Its features: A's edge and
// B's edge l, or, when the polygon edge runs along B's edge l', the vertex l' and l
// share, so that corners keep vertex ids (and exact heights) where they have them.
RegionPoint clip_crossing(const BandHulls& f, const RegionPoint& cur, const RegionPoint& nx, double dc, double dn,
                          int l, int label_out) {
  RegionPoint q;
  const double t = std::clamp(dc / (dc - dn), 0.0, 1.0);
  q.p = {cur.p.x + t * (nx.p.x - cur.p.x), cur.p.y + t * (nx.p.y - cur.p.y)};
  q.label = label_out;
  if (cur.label >= 0) {  // A's edge crosses B's edge l
    q.fa = f.edge_a(cur.label);
    q.fb = f.edge_b(l);
  } else {  // along B's edge l' into B's edge l: their common vertex
    const int lp = -1 - cur.label;
    int h = -1;
    if ((lp + 1) % f.mb == l) h = l;
    else if ((l + 1) % f.mb == lp) h = lp;
    if (h >= 0) {
      const int lab = q.label;
      q = f.b_vertex(h);
      q.label = lab;
    } else {
      q.fa = f.region_a;
      q.fb = f.region_b;
    }
  }
  return q;
}

// Face on face: Sutherland-Hodgman, A's polygon clipped by B's edges, with the edge
// labels carried along so every output corner knows its features. `next` is scratch;
// the result is left in `poly`.
void polygon_on_polygon(const BandHulls& f, double eps2, std::vector<RegionPoint>& poly,
                        std::vector<RegionPoint>& next) {
  for (int h = 0; h < f.ma; ++h) {
    RegionPoint q = f.a_vertex(h);
    q.label = h;
    poly.push_back(q);
  }
  for (int l = 0; l < f.mb && !poly.empty(); ++l) {
    const Pt2 e0 = f.pt_b(l), e1 = f.pt_b(l + 1);
    std::vector<RegionPoint>& nxt = next;
    nxt.clear();
    const int np = static_cast<int>(poly.size());
    for (int k = 0; k < np; ++k) {
      const RegionPoint& cur = poly[static_cast<std::size_t>(k)];
      const RegionPoint& nx = poly[static_cast<std::size_t>((k + 1) % np)];
      const double dc = cross2(e0, e1, cur.p), dn = cross2(e0, e1, nx.p);
      const bool cin = dc >= -eps2, nin = dn >= -eps2;
      if (cin) {
        nxt.push_back(cur);
        if (!nin) nxt.push_back(clip_crossing(f, cur, nx, dc, dn, l, -1 - l));
      } else if (nin) {
        nxt.push_back(clip_crossing(f, cur, nx, dc, dn, l, cur.label));
      }
    }
    poly.swap(nxt);
  }
}

// Every region point lifted onto both surfaces into sc.candidates: its gap, and the
// point midway along n. A point within kSamePoint L of an earlier one is that point.
void lift_region(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n, const PlaneBasis& basis,
                 double L, const Supports& sup, ManifoldScratch& sc) {
  std::vector<ContactPoint>& cand = sc.candidates;
  cand.clear();
  for (const RegionPoint& q : sc.poly) {
    bool dup = false;
    for (const ContactPoint& c : cand) {
      const Pt2 p = basis.to2(c.point);
      dup = dup || dist2(p, q.p) <= kSamePoint * L;
    }
    if (dup) continue;
    const Vec3 x0 = basis.to3(q.p);
    const double ta = q.va >= 0 ? n.dot(a.world_vertices[q.va]) : lift_a(sc.faces_a, x0, sup.ha);
    const double tb = q.vb >= 0 ? n.dot(b.world_vertices[q.vb]) : lift_b(sc.faces_b, x0, sup.hb);
    ContactPoint c;
    c.point = x0 + n * (0.5 * (ta + tb));
    c.normal = n;
    c.gap = ta - tb;
    c.feature_a = q.fa;
    c.feature_b = q.fb;
    cand.push_back(c);
  }
}

}  // namespace

void build_manifold(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n, ContactManifold& out) {
  thread_local ManifoldScratch sc;
  out.count = 0;
  const ConvexPolyhedron& A = *a.shape;
  const ConvexPolyhedron& B = *b.shape;
  const double L = pair_length(a, b);
  const double band = kBand * std::min(a.scale * A.bounding_radius, b.scale * B.bounding_radius);
  const double eps2 = kClipEps * L * L;  // doubled-area tolerance of the 2-D tests
  const double eps1 = kClipEps * L;
  const PlaneBasis basis = plane_basis(n);
  const Supports sup = band_vertices(a, b, n, band, basis, sc);

  hull_2d(sc.pa, eps2, sc.order, sc.hull_a);
  hull_2d(sc.pb, eps2, sc.order, sc.hull_b);
  collapse_short_hull(sc.hull_a, sc.pa, L);
  collapse_short_hull(sc.hull_b, sc.pb, L);
  BandHulls f;
  f.A = &A;
  f.B = &B;
  f.sc = &sc;
  f.ma = static_cast<int>(sc.hull_a.size());
  f.mb = static_cast<int>(sc.hull_b.size());
  // A side whose band feature is one vertex needs neither its faces nor its reference
  // face: every region point is then that vertex (exact height, vertex id).
  sc.faces_a.clear();
  sc.faces_b.clear();
  const int ref_a = f.ma >= 2 ? side_faces(a, sc.band_a, -1.0, n, sc, sc.faces_a) : -1;
  const int ref_b = f.mb >= 2 ? side_faces(b, sc.band_b, +1.0, n, sc, sc.faces_b) : -1;

  // Whole-feature ids: vertex, edge, or the reference face.
  const std::int32_t face_a = feature_id(FeatureKind::Face, std::max(ref_a, 0));
  const std::int32_t face_b = feature_id(FeatureKind::Face, std::max(ref_b, 0));
  f.region_a = f.ma == 1 ? feature_id(FeatureKind::Vertex, f.vert_a(0))
               : f.ma == 2 ? edge_or(A, f.vert_a(0), f.vert_a(1), face_a) : face_a;
  f.region_b = f.mb == 1 ? feature_id(FeatureKind::Vertex, f.vert_b(0))
               : f.mb == 2 ? edge_or(B, f.vert_b(0), f.vert_b(1), face_b) : face_b;

  // The region, by the shapes of the two band features (hull sizes 1, 2 or more).
  sc.poly.clear();
  if (f.ma == 1 && f.mb == 1) {
    vertex_on_vertex(f, sc.poly);
  } else if (f.ma == 1) {
    sc.poly.push_back(f.a_vertex(0));  // a vertex of A on B's edge or face
  } else if (f.mb == 1) {
    sc.poly.push_back(f.b_vertex(0));
  } else if (f.ma == 2 && f.mb == 2) {
    edge_on_edge(f, eps1, sc.poly);
  } else if (f.ma == 2 || f.mb == 2) {
    segment_in_polygon(f, eps1, eps2, sc.poly);
  } else {
    polygon_on_polygon(f, eps2, sc.poly, sc.next);
  }

  lift_region(a, b, n, basis, L, sup, sc);
  std::vector<ContactPoint>& cand = sc.candidates;
  if (cand.empty()) {
    // The band features do not overlap in projection (rounding at a corner): one point
    // between the two supporting vertices.
    ContactPoint c;
    c.point = 0.5 * (a.world_vertices[sup.sa] + b.world_vertices[sup.sb]);
    c.normal = n;
    c.gap = sup.ha - sup.hb;
    c.feature_a = feature_id(FeatureKind::Vertex, sup.sa);
    c.feature_b = feature_id(FeatureKind::Vertex, sup.sb);
    cand.push_back(c);
  }
  // At most 4 points, those in contact first: every point pressed in (gap <= 0), and
  // those within kRegionTouch L of the deepest or of touching. A region tilted by 1e-5
  // over a face is in the band at all its corners, and reducing them all by area could
  // drop the second corner that carries the load for one 3e-5 clear of the other body,
  // so that a loaded pair of a resting bed loses a support point every few steps and the
  // bed around it needs about four times the sweeps (docs/performance.md).
  double g_min = kInf;
  for (const ContactPoint& c : cand) g_min = std::min(g_min, c.gap);
  reduce_touching_first(cand, std::max(g_min, 0.0) + kRegionTouch * L, out);
}

}  // namespace ratchet::cp_detail

// Common Plane narrow phase: exact plane by SAT (overlap) or GJK (separation), then the
// contact region by clipping. See common_plane.hpp for the method and its sources.
#include "ratchet/contact/common_plane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ratchet/contact/manifold_reduction.hpp"

namespace ratchet {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------
// Tolerances. L is the pair's length scale, the sum of the two bounding radii
// (world units), so every tolerance below scales with the particles.
// ---------------------------------------------------------------------------------

// GJK stops when |v| - s(v/|v|) <= kGjkRelative |v|: the upper bound |v| and the lower
// bound s agree to 1e-14 relative, a few ulps above double rounding of the dot products.
constexpr double kGjkRelative = 1e-14;
// A polytope pair converges in far fewer support mappings (each one strictly lowers
// |v| on a finite vertex set); the cap only guards against rounding cycles.
constexpr int kGjkMaxIterations = 64;
// |v| below 1e-13 L: the bodies touch to rounding; GJK cannot give a direction, so the
// pair goes to the SAT, which is exact for touching and overlapping bodies.
constexpr double kGjkTouch = 1e-13;
// Safety added to the SAT pruning bound: it covers the rounding (~1e-15 L) of the few
// dot products in the bound, so pruning never drops an axis that could win.
constexpr double kPruneSafety = 1e-12;
// Edge pairs with sin(angle) < 1e-10 are parallel: their Minkowski "face" is a segment
// whose neighbours are face axes, and skipping it changes the depth by at most
// |edge| sin(angle) <= 1e-10 L (argued in sat_search below).
constexpr double kParallelEdgesSin2 = 1e-20;
// Triangles/tetrahedra of the GJK simplex thinner than this (relative) are degenerate
// and handled through their edges/faces.
constexpr double kDegenerateSin2 = 1e-24;
constexpr double kDegenerateVolume = 1e-13;
// An edge-pair axis within 1e-9 L of the best face axis is a candidate tie (rounding of
// the cross product is far smaller); only then are both scanned to pick the winner.
constexpr double kTieRescan = 1e-9;
// The SAT re-derives its pruning bounds from a better face axis only when that axis
// improves on the start by more than 1e-6 L (a tie or a rounding change is not worth
// the cost; any reference vertices give valid bounds).
constexpr double kRebound = 1e-6;
// Gram-Schmidt acceptance of a feature direction when polishing the GJK normal.
constexpr double kSpanRelative = 1e-8;
// Certificate (below): directions of D's facets farther than kCertFarAngle from the
// cached facet's normal are bounded by a scan at the step that made the certificate;
// nearer ones by the facet's own geometry at the current step.
constexpr double kCertFarAngle = 0.5;   // rad, about 29 degrees
// Facets within kCertEnum of the facet normal are evaluated one by one (a resting
// contact's competitors lie a rounding-sized angle from it); the disk bound covers the
// rest of the near region, which grows with sin(kCertEnum).
constexpr double kCertEnum = 0.02;      // rad, about 1 degree
// The features listed for that enumeration cover the facets within kCertEnum while the
// facet normal and B's orientation in A's frame have turned by less than kCertTurn.
constexpr double kCertTurn = 0.01;      // rad
// The far scan proves its bound against s_F - kCertSlack L (facets above that are
// evaluated): the certificate then lasts while the pair moves less than about that.
constexpr double kCertSlack = 0.02;
// Every other facet must stay kCertMargin L below the cached one: this covers the
// rounding of the values the search would compute (a face value ~1e-15 L; an edge-pair
// value eps / sin(angle) L, below 1e-6 L as sin >= 1e-10 by kParallelEdgesSin2) and
// kTieRescan, so the search could not have chosen another facet.
constexpr double kCertMargin = 1e-5;

// Contact band: the vertices of each body within kBand r of its own supporting plane
// (r: the smaller particle's bounding radius) form its contact feature. A face tilted
// by less than ~1e-3 rad against the plane thus still counts as lying on it, which the
// 1e-4-level rotations per step of a quasi-static bed need for a face on a face to keep
// its 4 corners; a vertex 1e-3 r off the plane is not in contact. The band is taken on
// each side separately, so it does not depend on the gap (deep overlaps included).
constexpr double kBand = 1e-3;
// 2-D clipping: a point is inside an edge's half-plane up to 1e-12 L (rounding of the
// projections), points closer than 1e-9 L are the same contact point.
constexpr double kClipEps = 1e-12;
constexpr double kSamePoint = 1e-9;
// Two band segments (edge-edge) closer to parallel than sin = 1e-3 touch along a line:
// they give the two ends of their overlap, not a single crossing point.
constexpr double kParallelSegmentsSin = 1e-3;
// Region points within kRegionTouch L of touching (or of the deepest point) are in
// contact when the region is reduced to 4 points: well above the overlaps a resting bed
// keeps (1e-9 to 1e-6) and below the lift of a corner of a face tilted by the motion of
// a few steps.
constexpr double kRegionTouch = 1e-6;
// Faces steeper than this against the plane (|m.n| < 1e-3) are not used to lift a 2-D
// point onto the surface: the division by m.n would amplify rounding by > 1e3.
constexpr double kSteep = 1e-3;

// The SAT's hot loops read the shape's arrays through raw pointers.
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
static_assert(sizeof(std::array<int, 2>) == 2 * sizeof(int), "edge_faces entries must be 2 packed ints");

int vertex_count(const PolyhedronView& p) { return static_cast<int>(p.shape->vertices.size()); }

double pair_length(const PolyhedronView& a, const PolyhedronView& b) {
  return a.scale * a.shape->bounding_radius + b.scale * b.shape->bounding_radius;
}

// argmin_i n.v_i and argmax_i n.v_i, lowest index on ties.
int argmin_dot(const Vec3* v, int count, const Vec3& n, double& h) {
  int best = 0;
  double hb = n.dot(v[0]);
  for (int i = 1; i < count; ++i) {
    const double x = n.dot(v[i]);
    if (x < hb) { hb = x; best = i; }
  }
  h = hb;
  return best;
}
int argmax_dot(const Vec3* v, int count, const Vec3& n, double& h) {
  int best = 0;
  double hb = n.dot(v[0]);
  for (int i = 1; i < count; ++i) {
    const double x = n.dot(v[i]);
    if (x > hb) { hb = x; best = i; }
  }
  h = hb;
  return best;
}

// s(n) with the support vertices: ia touches the plane from A's side, ib from B's.
struct AxisValue {
  double s = -kInf;
  int ia = 0;
  int ib = 0;
};
AxisValue evaluate_axis(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n) {
  AxisValue r;
  double ha = 0.0, hb = 0.0;
  r.ia = argmin_dot(a.world_vertices, vertex_count(a), n, ha);
  r.ib = argmax_dot(b.world_vertices, vertex_count(b), n, hb);
  r.s = ha - hb;
  return r;
}

// ---------------------------------------------------------------------------------
// GJK on D = A - B (Gilbert, Johnson & Keerthi 1988; closest points on the simplex by
// Voronoi regions, Ericson 2005, s. 5.1.2-5.1.6). v is the point of the current simplex
// closest to the origin; its direction is the normal from B towards A.
// ---------------------------------------------------------------------------------

struct SimplexVertex {
  Vec3 w = Vec3::Zero();  // a_ia - b_ib
  int ia = 0;
  int ib = 0;
};

struct Simplex {
  std::array<SimplexVertex, 4> v{};
  int n = 0;
};

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

struct GjkOutcome {
  bool proven_apart = false;  // a plane with s > 0 was found and GJK converged
  bool early_out = false;     // s > cutoff found
  double s = -kInf;           // best lower bound s(n) seen
  Vec3 n = Vec3::UnitZ();     // its direction
  Vec3 v = Vec3::Zero();      // final closest point of the simplex (the link, up to rounding)
  Simplex simplex;            // final simplex (its vertices are the closest features)
  int iterations = 0;
};

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

// ---------------------------------------------------------------------------------
// SAT over the facets of D with pruning (Gregorius 2013 for the Gauss-map test).
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
// ---------------------------------------------------------------------------------

struct Candidate {
  double s = -kInf;
  Vec3 n = Vec3::UnitZ();
  PlaneFeature kind = PlaneFeature::None;
  int index_a = -1;
  int index_b = -1;
};

// A facet replaces the best only if strictly better, except that it replaces a bare
// direction (Axis/Simplex start) on a tie: facet normals are exact.
void offer(Candidate& best, double s, const Vec3& n, PlaneFeature kind, int ia, int ib) {
  const bool bare = best.kind == PlaneFeature::Axis || best.kind == PlaneFeature::Simplex ||
                    best.kind == PlaneFeature::None;
  if (s > best.s || (s == best.s && bare && kind != PlaneFeature::Axis)) {
    best.s = s;
    best.n = n;
    best.kind = kind;
    best.index_a = ia;
    best.index_b = ib;
  }
}

// Inradius about the centre of mass (world units), or a valid lower bound of the
// support function when the centre were outside (never for a hull about its centroid).
double inradius(const PolyhedronView& p) {
  const double rho = p.shape->min_face_offset;
  return rho > 0.0 ? p.scale * rho : -p.scale * p.shape->bounding_radius;
}

// Upper bound over the arc between unit p and q of a linear function with end values
// m_p, m_q; cos_theta = p.q.
bool arc_may_exceed(double m_p, double m_q, double cos_theta, double target) {
  const double m = std::max(m_p, m_q);
  if (m > target) return true;
  if (m <= 0.0) return false;  // the arc's bound is m itself
  // 0 < m <= target: m / cos(theta/2) > target  <=>  2 m^2 > target^2 (1 + cos theta)
  return 2.0 * m * m > target * target * (1.0 + cos_theta);
}

struct EdgeData {
  int e;
  Vec3 n1, n2;    // world normals of the edge's two faces
  Vec3 cross;     // n2 x n1 (for B this equals (-n2) x (-n1))
  Vec3 dir;       // edge direction (world, unnormalised)
  Vec3 p;         // first vertex (world)
};

// The facet of D spanned by edge ea of A and edge eb of B, if their Gauss-map arcs
// cross: its value s and normal n (from B towards A). The SAT, the certificate's scans
// and its near check all evaluate edge pairs here, so they get the same bits.
bool edge_pair_facet(const EdgeData& ea, const EdgeData& eb, double& s, Vec3& n) {
  // Gregorius 2013, IsMinkowskiFace: arcs (a1, a2) of A and (-b1, -b2) of -B cross.
  const double cba = -eb.n1.dot(ea.cross), dba = -eb.n2.dot(ea.cross);
  const double adc = ea.n1.dot(eb.cross), bdc = ea.n2.dot(eb.cross);
  if (!(cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0)) return false;
  Vec3 nout = ea.dir.cross(eb.dir);  // outward from A, inside A's arc (n1, n2)
  const double len2 = nout.squaredNorm();
  // Parallel edges: the facet of D they would span has zero area; its neighbours are
  // face facets whose plane distance differs by at most |edge| sin(angle) (the
  // nearest-boundary point lies within that width of them).
  if (!(len2 > kParallelEdgesSin2 * ea.dir.squaredNorm() * eb.dir.squaredNorm())) return false;
  if (nout.dot(ea.n1 + ea.n2) < 0.0) nout = -nout;
  nout /= std::sqrt(len2);
  // A's support along nout is its edge, B's support along -nout is its edge, so
  // s(-nout) = nout.(q - p).
  s = nout.dot(eb.p - ea.p);
  n = -nout;
  return true;
}

// Edge e of p as the SAT reads it (world face normals, direction, first vertex).
EdgeData edge_data(const PolyhedronView& p, int e) {
  const ConvexPolyhedron& P = *p.shape;
  const int f1 = P.edge_faces[static_cast<std::size_t>(e)][0], f2 = P.edge_faces[static_cast<std::size_t>(e)][1];
  EdgeData ed;
  ed.e = e;
  ed.n1 = p.face_normal(f1);
  ed.n2 = p.face_normal(f2);
  ed.cross = ed.n2.cross(ed.n1);
  const auto& ev = P.edges[static_cast<std::size_t>(e)];
  ed.p = p.world_vertices[ev[0]];
  ed.dir = p.world_vertices[ev[1]] - ed.p;
  return ed;
}

// Reference vertices per side for bound (2): 4 covers the corners of a quadrilateral
// contact face. They are tried one at a time (best support first) and only until one
// of them prunes the axis, so most faces cost one value.
constexpr int kRefVertices = 4;

// Bounds of the face axes of one body p, whose axis is n = sign * (outward normal):
// centre[f] = n.d for bound (1), and bound (2) for reference vertex k, the signed
// distance of the other body's vertex x_k from the plane of f, computed on demand in
// p's body frame (3 multiplications per value).
struct SideBounds {
  std::vector<double> centre;
  std::vector<std::array<double, kRefVertices>> vertex;
  std::vector<int> done;  // reference values computed so far, per face
  // hot[f]: bound (2) with the first reference exceeds min(lim, 0), necessary for an
  // edge of f to pass (see active_edges); candidates: faces whose two bounds beat lim.
  std::vector<unsigned char> hot;
  std::vector<int> candidates;
  const ConvexPolyhedron* shape = nullptr;
  double scale = 1.0;
  std::array<Vec3, kRefVertices> x_body{};
  int refs = 0;

  double value(int f, int k) {
    const std::size_t fi = static_cast<std::size_t>(f);
    for (int& j = done[fi]; j <= k; ++j)
      vertex[fi][static_cast<std::size_t>(j)] =
          scale * (shape->face_normals[fi].dot(x_body[static_cast<std::size_t>(j)]) - shape->face_offsets[fi]);
    return vertex[fi][static_cast<std::size_t>(k)];
  }
};

struct SatScratch {
  SideBounds a, b;
  std::vector<EdgeData> ea, eb;
};

// Face axis of A: n = -m (m its outward world normal), s = min_b (m.b) - d_f.
double face_a_value(const PolyhedronView& a, const PolyhedronView& b, int f, Vec3& n) {
  const Vec3 m = a.face_normal(f);
  n = -m;
  double hb = 0.0;
  argmin_dot(b.world_vertices, vertex_count(b), m, hb);
  return hb - a.face_offset(f);
}
// Face axis of B: n = m, s = min_a (m.a) - d_g.
double face_b_value(const PolyhedronView& a, const PolyhedronView& b, int g, Vec3& n) {
  n = b.face_normal(g);
  double ha = 0.0;
  argmin_dot(a.world_vertices, vertex_count(a), n, ha);
  return ha - b.face_offset(g);
}

// The k best supports of body q along direction u (largest u.x first, lowest index on
// ties); k = min(kRefVertices, vertex count).
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

// Can face axis f beat lim? Bound (1) first (already computed), then bound (2) per
// reference vertex until one rules it out.
bool face_may_win(SideBounds& sb, int f, double rho, double lim) {
  if (!(sb.centre[static_cast<std::size_t>(f)] - rho > lim)) return false;
  for (int k = 0; k < sb.refs; ++k)
    if (!(sb.value(f, k) > lim)) return false;
  return true;
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

// Current axis of a cached facet, or false if the cache holds none.
bool cached_axis(const PolyhedronView& a, const PolyhedronView& b, const CommonPlaneCache& cache, Vec3& n) {
  switch (cache.kind) {
    case PlaneFeature::FaceA:
      if (cache.index_a < 0 || cache.index_a >= static_cast<int>(a.shape->faces.size())) return false;
      n = -a.face_normal(cache.index_a);
      return true;
    case PlaneFeature::FaceB:
      if (cache.index_b < 0 || cache.index_b >= static_cast<int>(b.shape->faces.size())) return false;
      n = b.face_normal(cache.index_b);
      return true;
    case PlaneFeature::EdgeEdge: {
      if (cache.index_a < 0 || cache.index_a >= static_cast<int>(a.shape->edges.size())) return false;
      if (cache.index_b < 0 || cache.index_b >= static_cast<int>(b.shape->edges.size())) return false;
      const auto& ea = a.shape->edges[static_cast<std::size_t>(cache.index_a)];
      const auto& eb = b.shape->edges[static_cast<std::size_t>(cache.index_b)];
      const Vec3 u = a.world_vertices[ea[1]] - a.world_vertices[ea[0]];
      const Vec3 w = b.world_vertices[eb[1]] - b.world_vertices[eb[0]];
      Vec3 c = u.cross(w);
      const double len2 = c.squaredNorm();
      if (!(len2 > kParallelEdgesSin2 * u.squaredNorm() * w.squaredNorm())) return false;
      c /= std::sqrt(len2);
      n = c.dot(cache.normal) < 0.0 ? Vec3(-c) : c;
      return true;
    }
    default:
      return false;
  }
}

void store(CommonPlaneCache& cache, const Candidate& c) {
  cache.certificate.valid = false;
  cache.valid = true;
  cache.normal = c.n;
  cache.kind = c.kind;
  cache.index_a = c.index_a;
  cache.index_b = c.index_b;
  cache.simplex_count = 0;
}

void store_simplex(CommonPlaneCache& cache, const Vec3& n, const Simplex& s) {
  cache.certificate.valid = false;
  cache.valid = true;
  cache.normal = n;
  cache.kind = PlaneFeature::Simplex;
  cache.index_a = cache.index_b = -1;
  cache.simplex_count = s.n;
  for (int k = 0; k < s.n; ++k)
    cache.simplex[static_cast<std::size_t>(k)] = {s.v[static_cast<std::size_t>(k)].ia, s.v[static_cast<std::size_t>(k)].ib};
}

Simplex single_vertex(const PolyhedronView& a, const PolyhedronView& b, int ia, int ib) {
  Simplex s;
  s.n = 1;
  s.v[0].ia = ia;
  s.v[0].ib = ib;
  s.v[0].w = a.world_vertices[ia] - b.world_vertices[ib];
  return s;
}

// ---------------------------------------------------------------------------------
// Certificate: a proof that the cached facet F of D is still the best one, so that the
// SAT (sat_search) can be skipped with the result it would give, bit for bit. In a
// resting bed most overlapping pairs keep their facet for many steps, and the SAT
// bounds every face and edge of both bodies to show it again (docs/performance.md).
//
// h(nu) = max_{d in D} nu.d is the support function of D = A - B; a facet G with outward
// normal nu_G has s_G = -h(nu_G), and the SAT returns the facet of largest s, F, with
// delta = h(nu_F) >= 0 the overlap. theta is the angle between nu and nu_F. Three
// regions of directions, which together cover the sphere:
//  * Nearest, theta < kCertEnum: these facets are enumerated (the faces of both bodies
//    whose normals lie there, the edge pairs of the edges nearly orthogonal to nu_F;
//    listed when the certificate is made, with room for the pair to turn by kCertTurn)
//    and their values computed exactly as the SAT computes them: none may exceed s_F.
//    A resting contact lies flat (an edge or face on a face), so its competitors are
//    here, a rounding-sized distance below F.
//  * Near, kCertEnum <= theta <= theta0: if the origin's projection onto F's plane lies
//    in F with a disk of radius m around it, D contains that disk, so
//    h(nu) >= delta cos(theta) + m sin(theta), i.e. for 0 < theta < pi / 2
//    h(nu) - delta >= sin(theta) (m - delta tan(theta / 2))
//                  >= sin(kCertEnum) (m - delta tan(theta0 / 2)).
//  * Far, theta > kCertFarAngle from the facet normal of the step that made the
//    certificate: while the origin is inside D, h has no local minimum on the sphere
//    but at facet normals (it is linear on each vertex cell and positive), so its
//    minimum over the region is attained at a facet normal in it or on its boundary
//    circle, where the disk bound holds. That step bounds s over the region by a scan
//    with the SAT's bounds (far_bound). Later, every point of D has moved by at most mu
//    in A's frame, so h of a fixed direction of A's frame by at most mu: the region's
//    facets have s <= far_bound + mu.
// theta0 is kCertFarAngle plus the angle nu_F has turned in A's frame since (at most
// kCertTurn). The near and far bounds must leave every facet there kCertMargin L below F.
// ---------------------------------------------------------------------------------

// Radius of the largest disk about world point x (on face f's plane) inside face f.
double face_disk(const PolyhedronView& p, int f, const Vec3& x) {
  const ConvexPolyhedron& P = *p.shape;
  const Vec3 xb = p.R.transpose() * (x - p.center) / p.scale;
  double lo = kInf;
  for (int k = P.face_side_start[static_cast<std::size_t>(f)]; k < P.face_side_start[static_cast<std::size_t>(f) + 1]; ++k)
    lo = std::min(lo, P.face_side_offsets[static_cast<std::size_t>(k)] - P.face_side_normals[static_cast<std::size_t>(k)].dot(xb));
  return p.scale * lo;
}

bool certifiable(const PolyhedronView& p) {
  return p.shape->face_side_start.size() == p.shape->faces.size() + 1 &&
         p.shape->edge_directions.size() == p.shape->edges.size();
}

// Radius of the disk about the origin's projection that facet F (CP normal F.n, value
// s, supports av along F.n) holds: F = face of A - vertex of B, vertex of A - face of B,
// or edge of A - edge of B (a parallelogram). <= 0: the projection is not inside F.
double facet_disk(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                  const AxisValue& av) {
  const double delta = -s;
  switch (F.kind) {
    case PlaneFeature::FaceA:  // n = -m: the point of face f above B's vertex
      return face_disk(a, F.index_a, b.world_vertices[av.ib] - delta * F.n);
    case PlaneFeature::FaceB:  // n = m
      return face_disk(b, F.index_b, a.world_vertices[av.ia] + delta * F.n);
    case PlaneFeature::EdgeEdge: {
      const auto& ea = a.shape->edges[static_cast<std::size_t>(F.index_a)];
      const auto& eb = b.shape->edges[static_cast<std::size_t>(F.index_b)];
      const Vec3 &a0 = a.world_vertices[ea[0]], &b0 = b.world_vertices[eb[0]];
      const Vec3 u = a.world_vertices[ea[1]] - a0, w = b.world_vertices[eb[1]] - b0, r = a0 - b0;
      // Closest points a0 + sigma u and b0 + tau w of the two lines: the projection.
      const double uu = u.dot(u), uw = u.dot(w), ww = w.dot(w), ur = u.dot(r), wr = w.dot(r);
      const double den = uu * ww - uw * uw;
      if (!(den > 0.0)) return 0.0;
      const double sigma = (uw * wr - ww * ur) / den, tau = (uu * wr - uw * ur) / den;
      const double lu = std::sqrt(uu), lw = std::sqrt(ww);
      // A point sigma u + tau w of the parallelogram lies sigma |u| sin(phi) from its
      // side along w, and so on.
      return std::sqrt(den) / (lu * lw) * std::min({sigma * lu, (1.0 - sigma) * lu, tau * lw, (1.0 - tau) * lw});
    }
    default:
      return 0.0;
  }
}

// Lists in `cert` the features that can span a facet within kCertEnum of nu = -F.n
// while nu and B's orientation in A's frame turn by less than kCertTurn (see
// certificate_holds): faces within kCertEnum + kCertTurn of nu; edges e with
// |nu.e| <= 2 sin(kCertEnum / 2) + kCertTurn (a facet normal within theta of nu is
// orthogonal to both its edges, so each has |nu.e| <= |nu - n| = 2 sin(theta / 2)).
// Slightly wider than that, so rounding cannot leave one out. False if they do not fit.
bool list_nearest(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, PlaneCertificate& cert) {
  const Vec3 nu_a = a.R.transpose() * -F.n, nu_b = b.R.transpose() * -F.n;
  const double cos_face = std::cos(1.01 * (kCertEnum + kCertTurn));
  const double edge_cos = 1.01 * (2.0 * std::sin(0.5 * kCertEnum) + kCertTurn);
  int fa = 0, fb = 0, ea = 0, eb = 0;
  const ConvexPolyhedron &A = *a.shape, &B = *b.shape;
  if (A.faces.size() > 32767 || B.faces.size() > 32767 || A.edges.size() > 32767 || B.edges.size() > 32767) return false;
  for (std::size_t f = 0; f < A.faces.size(); ++f) {
    if ((F.kind == PlaneFeature::FaceA && F.index_a == static_cast<int>(f)) || A.face_normals[f].dot(nu_a) < cos_face) continue;
    if (fa == PlaneCertificate::kFaces) return false;
    cert.face_a[static_cast<std::size_t>(fa++)] = static_cast<std::int16_t>(f);
  }
  for (std::size_t g = 0; g < B.faces.size(); ++g) {
    if ((F.kind == PlaneFeature::FaceB && F.index_b == static_cast<int>(g)) || -B.face_normals[g].dot(nu_b) < cos_face) continue;
    if (fb == PlaneCertificate::kFaces) return false;
    cert.face_b[static_cast<std::size_t>(fb++)] = static_cast<std::int16_t>(g);
  }
  for (std::size_t e = 0; e < A.edges.size(); ++e) {
    if (!(std::abs(A.edge_directions[e].dot(nu_a)) <= edge_cos)) continue;
    if (ea == PlaneCertificate::kEdges) return false;
    cert.edge_a[static_cast<std::size_t>(ea++)] = static_cast<std::int16_t>(e);
  }
  for (std::size_t e = 0; e < B.edges.size(); ++e) {
    if (!(std::abs(B.edge_directions[e].dot(nu_b)) <= edge_cos)) continue;
    if (eb == PlaneCertificate::kEdges) return false;
    cert.edge_b[static_cast<std::size_t>(eb++)] = static_cast<std::int16_t>(e);
  }
  cert.faces_a = static_cast<std::int8_t>(fa);
  cert.faces_b = static_cast<std::int8_t>(fb);
  cert.edges_a = static_cast<std::int8_t>(ea);
  cert.edges_b = static_cast<std::int8_t>(eb);
  return true;
}

// The nearest region: the listed features' facets, evaluated as the SAT evaluates them.
// False if one could replace F (value s) in the SAT: a value above s (offer() keeps a
// facet on a tie), or (F an edge pair) a face within the SAT's tie rescan of s, whose
// outcome depends on which faces the SAT's pruning let through.
bool nearest_below(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                   const PlaneCertificate& cert) {
  const bool edge_start = F.kind == PlaneFeature::EdgeEdge;
  const double face_limit = edge_start ? s - kTieRescan * pair_length(a, b) : s;
  auto face_replaces = [&](double v) { return edge_start ? v >= face_limit : v > s; };
  Vec3 n;
  for (int k = 0; k < cert.faces_a; ++k)
    if (face_replaces(face_a_value(a, b, cert.face_a[static_cast<std::size_t>(k)], n))) return false;
  for (int k = 0; k < cert.faces_b; ++k)
    if (face_replaces(face_b_value(a, b, cert.face_b[static_cast<std::size_t>(k)], n))) return false;
  std::array<EdgeData, PlaneCertificate::kEdges> eb;
  for (int k = 0; k < cert.edges_b; ++k) eb[static_cast<std::size_t>(k)] = edge_data(b, cert.edge_b[static_cast<std::size_t>(k)]);
  for (int i = 0; i < cert.edges_a; ++i) {
    const EdgeData x = edge_data(a, cert.edge_a[static_cast<std::size_t>(i)]);
    for (int k = 0; k < cert.edges_b; ++k) {
      const EdgeData& y = eb[static_cast<std::size_t>(k)];
      if (F.kind == PlaneFeature::EdgeEdge && x.e == F.index_a && y.e == F.index_b) continue;
      double v = 0.0;
      if (edge_pair_facet(x, y, v, n) && v > s) return false;
    }
  }
  return true;
}

// Upper bound of s over the facets of D at least kCertFarAngle from nu = -F.n: the
// SAT's bounds (sat_search) against lim = F.s - kCertSlack L, the facets that pass
// them evaluated, the nearer ones left to the other two regions.
double far_scan(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F) {
  thread_local SatScratch sc;
  const Vec3 nu = -F.n;
  const Vec3 d = a.center - b.center;
  const double rho = inradius(a) + inradius(b);
  const double L = pair_length(a, b);
  const double lim = F.s - kCertSlack * L;
  const double cos_far = std::cos(kCertFarAngle);
  std::array<int, kRefVertices> ref_a{}, ref_b{};
  const int na = top_supports(a, nu, ref_a);
  const int nb = top_supports(b, F.n, ref_b);
  face_bounds(a, -1.0, d, b, ref_b, nb, rho, lim, sc.a);
  face_bounds(b, +1.0, d, a, ref_a, na, rho, lim, sc.b);
  double top = lim + kPruneSafety * L;  // what every pruned facet is proven below
  Vec3 n;
  for (const int f : sc.a.candidates)
    if (face_may_win(sc.a, f, rho, lim) && a.face_normal(f).dot(nu) < cos_far) top = std::max(top, face_a_value(a, b, f, n));
  for (const int g : sc.b.candidates)
    if (face_may_win(sc.b, g, rho, lim) && -b.face_normal(g).dot(nu) < cos_far) top = std::max(top, face_b_value(a, b, g, n));
  active_edges(a, sc.a, rho, lim, sc.ea);
  if (sc.ea.empty()) return top;
  active_edges(b, sc.b, rho, lim, sc.eb);
  for (const EdgeData& ea : sc.ea)
    for (const EdgeData& eb : sc.eb) {
      double v = 0.0;
      if (edge_pair_facet(ea, eb, v, n) && -n.dot(nu) < cos_far) top = std::max(top, v);
    }
  return top;
}

// Lower bound of h - delta over the near region for turn angle theta0 (see above).
double near_bound(double disk, double s, double theta0) {
  return std::sin(kCertEnum) * (disk + s * std::tan(0.5 * theta0));
}

// Makes the certificate of facet F (the SAT's result, s its scanned value <= 0) when
// the pair is certifiable now: the next steps then check it instead of searching.
void make_certificate(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                      PlaneCertificate& cert) {
  cert.valid = false;
  if (!(s <= 0.0) || !certifiable(a) || !certifiable(b)) return;
  const double margin = kCertMargin * pair_length(a, b);
  const AxisValue av = evaluate_axis(a, b, F.n);
  const double disk = facet_disk(a, b, F, s, av);
  if (!(near_bound(disk, s, kCertFarAngle + kCertTurn) > margin)) return;
  if (!list_nearest(a, b, F, cert) || !nearest_below(a, b, F, s, cert)) return;
  Candidate at = F;
  at.s = s;
  const double circle = -(-s * std::cos(kCertFarAngle) + disk * std::sin(kCertFarAngle));
  cert.far_bound = std::max(far_scan(a, b, at), circle);
  if (!(cert.far_bound + margin < s)) return;  // could never hold
  cert.rotation = a.R.transpose() * b.R;
  cert.offset = a.R.transpose() * (b.center - a.center);
  cert.scale_a = a.scale;
  cert.scale_b = b.scale;
  cert.normal_a = a.R.transpose() * (-F.n);
  cert.valid = true;
}

// Does the certificate prove that the start facet F (its scanned value F.s, supports
// av) is what the SAT would return at the current pose?
bool certificate_holds(const PolyhedronView& a, const PolyhedronView& b, const PlaneCertificate& cert,
                       const Candidate& F, const AxisValue& av) {
  if (!cert.valid || !(F.s <= 0.0)) return false;
  const double margin = kCertMargin * pair_length(a, b);
  const Mat3 Rt = a.R.transpose();
  const Mat3 rotation = Rt * b.R;
  const Vec3 offset = Rt * (b.center - a.center);
  // Largest displacement of a point of D in A's frame since the certificate was made.
  const double mu = std::abs(a.scale - cert.scale_a) * a.shape->bounding_radius + (offset - cert.offset).norm() +
                    (b.scale * rotation - cert.scale_b * cert.rotation).norm() * b.shape->bounding_radius;
  if (!(cert.far_bound + mu + margin < F.s)) return false;
  // Turn of nu_F and of B in A's frame (|R1 - R0|_F = 2 sqrt(2) sin(angle / 2); acos
  // and asin lose ~1e-8 rad near their ends: add 1e-7).
  const double turn = std::acos(std::clamp((Rt * (-F.n)).dot(cert.normal_a), -1.0, 1.0)) + 1e-7;
  const double spin = 2.0 * std::asin(std::min(1.0, (rotation - cert.rotation).norm() / (2.0 * std::sqrt(2.0)))) + 1e-7;
  if (!(turn + spin <= kCertTurn)) return false;
  if (!(near_bound(facet_disk(a, b, F, F.s, av), F.s, kCertFarAngle + turn) > margin)) return false;
  return nearest_below(a, b, F, F.s, cert);
}

// The common plane; with a finite cutoff it may stop as soon as g > cutoff is proven.
CommonPlaneResult solve(const PolyhedronView& a, const PolyhedronView& b, CommonPlaneCache& cache,
                        double cutoff) {
  CommonPlaneResult r;
  Candidate best;
  Simplex seed;
  bool try_gjk = false;

  // The start axis's value, kept: when no facet beats the start (a warm-started resting
  // contact) finish() reports it without a second scan of the vertices.
  bool start_known = false;
  Vec3 start_n = Vec3::Zero();
  double start_s = 0.0;
  AxisValue start_av;
  auto finish = [&](const Candidate& c) {
    // The gap reported is s(n) over the world vertices at the normal reported.
    r.normal = c.n;
    r.gap = start_known && c.n == start_n ? start_s : evaluate_axis(a, b, c.n).s;
    r.feature = c.kind;
    r.separated = r.gap > 0.0;
    return r;
  };
  auto early = [&](const Candidate& c) {
    r.normal = c.n;
    r.gap = c.s;
    r.feature = c.kind;
    r.separated = true;
    r.early_out = true;
    return r;
  };

  // 1. Start: the cached simplex (apart last step), the cached facet re-evaluated at the
  //    new poses, the cached normal, or cold the line of centres.
  const int nva = vertex_count(a), nvb = vertex_count(b);
  bool simplex_ok = cache.valid && cache.kind == PlaneFeature::Simplex && cache.simplex_count > 0;
  for (int k = 0; simplex_ok && k < cache.simplex_count; ++k) {
    const auto& p = cache.simplex[static_cast<std::size_t>(k)];
    simplex_ok = p[0] >= 0 && p[0] < nva && p[1] >= 0 && p[1] < nvb;
  }
  if (simplex_ok) {
    seed.n = cache.simplex_count;
    for (int k = 0; k < seed.n; ++k) {
      const auto& p = cache.simplex[static_cast<std::size_t>(k)];
      seed.v[static_cast<std::size_t>(k)] = single_vertex(a, b, p[0], p[1]).v[0];
    }
    try_gjk = true;
    best.kind = PlaneFeature::Simplex;
  } else {
    Vec3 n0;
    PlaneFeature kind = PlaneFeature::Axis;
    if (cache.valid && cached_axis(a, b, cache, n0)) {
      kind = cache.kind;
    } else if (cache.valid && cache.normal.squaredNorm() > 0.0) {
      n0 = cache.normal.normalized();
    } else {
      const Vec3 d = a.center - b.center;
      n0 = d.squaredNorm() > 0.0 ? Vec3(d.normalized()) : Vec3::UnitZ();
    }
    const AxisValue av = evaluate_axis(a, b, n0);
    start_av = av;
    ++r.sat_axes;
    start_known = true;
    start_n = n0;
    start_s = av.s;
    best.s = av.s;
    best.n = n0;
    best.kind = kind;
    if (kind != PlaneFeature::Axis) {
      best.index_a = cache.index_a;
      best.index_b = cache.index_b;
    }
    if (best.s > cutoff) {
      store(cache, best);
      return early(best);
    }
    if (best.s > 0.0) {
      seed = single_vertex(a, b, av.ia, av.ib);
      try_gjk = true;
    }
  }

  // 2. Apart (or apart last step): GJK distance.
  bool gjk_done = false;
  GjkOutcome go;
  if (try_gjk) {
    go = gjk(a, b, seed, cutoff);
    r.gjk_iterations += go.iterations;
    gjk_done = true;
    offer(best, go.s, go.n, PlaneFeature::Simplex, -1, -1);
    if (go.early_out) {
      store_simplex(cache, go.n, go.simplex);
      return early(best);
    }
  }

  // 3. Not proven apart: SAT over the facets of D (exact when they overlap).
  if (!(gjk_done && go.proven_apart)) {
    if (simplex_ok) {
      // Apart last step, touching or overlapping now: GJK may have enclosed the origin
      // before producing a useful bound, so the SAT starts from the cached normal, which
      // is within the step's motion of the optimum.
      const Vec3 n0 = cache.normal.squaredNorm() > 0.0 ? Vec3(cache.normal.normalized()) : Vec3::UnitZ();
      ++r.sat_axes;
      offer(best, evaluate_axis(a, b, n0).s, n0, PlaneFeature::Axis, -1, -1);
    }
    const bool facet_start = !simplex_ok && start_known &&
                             (best.kind == PlaneFeature::FaceA || best.kind == PlaneFeature::FaceB ||
                              best.kind == PlaneFeature::EdgeEdge);
    if (facet_start && certificate_holds(a, b, cache.certificate, best, start_av)) {
      // Proven: the SAT would keep the start facet, and report it as below.
      const PlaneCertificate cert = cache.certificate;
      store(cache, best);
      cache.certificate = cert;
      r.certified = true;
      return finish(best);
    }
    const Candidate start = best;
    Candidate best_face;
    if (best.kind == PlaneFeature::FaceA || best.kind == PlaneFeature::FaceB) best_face = best;
    sat_search(a, b, best, best_face, cutoff, r);
    if (best.s > cutoff) {
      store(cache, best);
      return early(best);
    }
    if (!(best.s > 0.0)) {
      // An edge pair lying in two (nearly) parallel faces ties with the face axis; its
      // cross-product normal carries eps / sin(crossing angle) of rounding. On a near
      // tie keep whichever normal achieves more when scanned (the face on equality).
      if (best.kind == PlaneFeature::EdgeEdge && best_face.s >= best.s - kTieRescan * pair_length(a, b) &&
          evaluate_axis(a, b, best_face.n).s >= evaluate_axis(a, b, best.n).s)
        best = best_face;
      store(cache, best);
      const CommonPlaneResult out = finish(best);
      // A certificate costs a second pass over the SAT's bounds: made only for a pair
      // that kept its facet from the last step, the kind that keeps it for many more.
      if (facet_start && best.kind == start.kind && best.index_a == start.index_a && best.index_b == start.index_b)
        make_certificate(a, b, best, out.gap, cache.certificate);
      return out;
    }
    // A facet separates them: the distance needs GJK, seeded at that facet's support pair.
    // Its value is replaced by the scanned one (an edge-pair value n.(q - p) can exceed
    // s(n) by rounding), so that GJK's scanned values compete on equal terms.
    const AxisValue av = evaluate_axis(a, b, best.n);
    best.s = av.s;
    go = gjk(a, b, single_vertex(a, b, av.ia, av.ib), cutoff);
    r.gjk_iterations += go.iterations;
    offer(best, go.s, go.n, PlaneFeature::Simplex, -1, -1);
    if (go.early_out) {
      store_simplex(cache, go.n, go.simplex);
      return early(best);
    }
  }

  // 4. Apart: the best of the facet/start axis, GJK's directions and the final link
  //    polished. (The best lower bound may come from an earlier, non-final simplex whose
  //    direction is off by far more than its small loss in s suggests: only the final
  //    link is the closest point.)
  Vec3 np;
  if (go.v.squaredNorm() > 0.0 && polish_normal(a, b, go.simplex, go.v.normalized(), np)) {
    const double s = evaluate_axis(a, b, np).s;
    if (s >= best.s) {
      best.s = s;
      best.n = np;
      best.kind = PlaneFeature::Simplex;
    }
  }
  store_simplex(cache, best.n, go.simplex);
  return finish(best);
}

// ---------------------------------------------------------------------------------
// Contact region: band features of each body, projected on the plane, clipped
// (Sutherland & Hodgman 1974, "Reentrant polygon clipping", CACM 17(1)), lifted back
// onto both surfaces.
// ---------------------------------------------------------------------------------

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

void build_manifold(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n, ContactManifold& out) {
  thread_local ManifoldScratch sc;
  out.count = 0;
  const ConvexPolyhedron& A = *a.shape;
  const ConvexPolyhedron& B = *b.shape;
  const int nva = vertex_count(a), nvb = vertex_count(b);
  const double L = pair_length(a, b);
  const double band = kBand * std::min(a.scale * A.bounding_radius, b.scale * B.bounding_radius);
  const double eps2 = kClipEps * L * L;  // doubled-area tolerance of the 2-D tests
  const double eps1 = kClipEps * L;

  // Plane basis (t1, t2, n), right-handed, from the axis least aligned with n.
  Eigen::Index k_min = 0;
  n.cwiseAbs().minCoeff(&k_min);
  const Vec3 t1 = Vec3::Unit(k_min).cross(n).normalized();
  const Vec3 t2 = n.cross(t1);
  auto to2 = [&](const Vec3& x) { return Pt2{t1.dot(x), t2.dot(x)}; };
  auto to3 = [&](const Pt2& p) { return Vec3(t1 * p.x + t2 * p.y); };

  // Band features: A's vertices near its lowest plane along n, B's near its highest.
  // The heights n.x of every vertex once (as argmin_dot / argmax_dot compute them), for
  // the supports and the band alike.
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
    if (sc.height_a[static_cast<std::size_t>(i)] <= ha + band) { sc.band_a.push_back(i); sc.pa.push_back(to2(a.world_vertices[i])); }
  for (int j = 0; j < nvb; ++j)
    if (sc.height_b[static_cast<std::size_t>(j)] >= hb - band) { sc.band_b.push_back(j); sc.pb.push_back(to2(b.world_vertices[j])); }

  // Faces touching the band (they carry the surface over the band region) and the
  // reference face of each side (most aligned with the plane).
  // Only faces turned towards the other body (sign m.n > kSteep) can carry the surface
  // over the band region: the support vertex's normal cone contains sign n, so one of
  // its faces always qualifies. The test runs in the body frame (3 multiplications).
  auto side_faces = [&](const PolyhedronView& p, const std::vector<int>& bandv, double sign,
                        std::vector<SideFace>& faces) {
    // Faces around the band vertices (vertex_face_list), each once, in ascending order so the
    // reference face is the same whatever the band's order: marked in a bit set, read
    // back word by word (was a sort and unique of the list for every pair).
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
  };
  hull_2d(sc.pa, eps2, sc.order, sc.hull_a);
  hull_2d(sc.pb, eps2, sc.order, sc.hull_b);
  auto collapse = [&](std::vector<int>& h, const std::vector<Pt2>& p) {
    if (h.size() == 2) {
      const Pt2 &p0 = p[static_cast<std::size_t>(h[0])], &p1 = p[static_cast<std::size_t>(h[1])];
      if (dist2(p0, p1) <= kSamePoint * L) h.resize(1);
    }
  };
  collapse(sc.hull_a, sc.pa);
  collapse(sc.hull_b, sc.pb);
  const int ma = static_cast<int>(sc.hull_a.size()), mb = static_cast<int>(sc.hull_b.size());
  // A side whose band feature is one vertex needs neither its faces nor its reference
  // face: every region point is then that vertex (exact height, vertex id).
  sc.faces_a.clear();
  sc.faces_b.clear();
  const int ref_a = ma >= 2 ? side_faces(a, sc.band_a, -1.0, sc.faces_a) : -1;
  const int ref_b = mb >= 2 ? side_faces(b, sc.band_b, +1.0, sc.faces_b) : -1;
  auto vert_a = [&](int h) { return sc.band_a[static_cast<std::size_t>(sc.hull_a[static_cast<std::size_t>(h % ma)])]; };
  auto vert_b = [&](int h) { return sc.band_b[static_cast<std::size_t>(sc.hull_b[static_cast<std::size_t>(h % mb)])]; };
  auto pt_a = [&](int h) { return sc.pa[static_cast<std::size_t>(sc.hull_a[static_cast<std::size_t>(h % ma)])]; };
  auto pt_b = [&](int h) { return sc.pb[static_cast<std::size_t>(sc.hull_b[static_cast<std::size_t>(h % mb)])]; };

  // Whole-feature ids: vertex, edge, or the reference face.
  const std::int32_t face_a = feature_id(FeatureKind::Face, std::max(ref_a, 0));
  const std::int32_t face_b = feature_id(FeatureKind::Face, std::max(ref_b, 0));
  const std::int32_t region_a = ma == 1 ? feature_id(FeatureKind::Vertex, vert_a(0))
                                : ma == 2 ? edge_or(A, vert_a(0), vert_a(1), face_a) : face_a;
  const std::int32_t region_b = mb == 1 ? feature_id(FeatureKind::Vertex, vert_b(0))
                                : mb == 2 ? edge_or(B, vert_b(0), vert_b(1), face_b) : face_b;
  auto edge_a = [&](int h) { return ma == 2 ? region_a : edge_or(A, vert_a(h), vert_a(h + 1), region_a); };
  auto edge_b = [&](int h) { return mb == 2 ? region_b : edge_or(B, vert_b(h), vert_b(h + 1), region_b); };
  auto a_vertex = [&](int h) {
    RegionPoint q;
    q.p = pt_a(h);
    q.va = vert_a(h);
    q.fa = feature_id(FeatureKind::Vertex, q.va);
    q.fb = region_b;
    return q;
  };
  auto b_vertex = [&](int h) {
    RegionPoint q;
    q.p = pt_b(h);
    q.vb = vert_b(h);
    q.fa = region_a;
    q.fb = feature_id(FeatureKind::Vertex, q.vb);
    return q;
  };

  std::vector<RegionPoint>& poly = sc.poly;
  poly.clear();
  if (ma == 1 && mb == 1) {
    RegionPoint q = a_vertex(0);
    const Pt2 pb = pt_b(0);
    q.p = {0.5 * (q.p.x + pb.x), 0.5 * (q.p.y + pb.y)};
    q.vb = vert_b(0);
    q.fb = feature_id(FeatureKind::Vertex, q.vb);
    poly.push_back(q);
  } else if (ma == 1) {
    poly.push_back(a_vertex(0));
  } else if (mb == 1) {
    poly.push_back(b_vertex(0));
  } else if (ma == 2 && mb == 2) {
    // Edge on edge: crossing point, or the ends of the overlap when (nearly) parallel.
    const Pt2 a0 = pt_a(0), a1 = pt_a(1), b0 = pt_b(0), b1 = pt_b(1);
    const double dax = a1.x - a0.x, day = a1.y - a0.y, dbx = b1.x - b0.x, dby = b1.y - b0.y;
    const double la = std::sqrt(dax * dax + day * day), lb = std::sqrt(dbx * dbx + dby * dby);
    const double cr = dax * dby - day * dbx;
    if (std::abs(cr) > kParallelSegmentsSin * la * lb) {
      const double wx = b0.x - a0.x, wy = b0.y - a0.y;
      const double t = std::clamp((wx * dby - wy * dbx) / cr, 0.0, 1.0);
      const double u = std::clamp((wx * day - wy * dax) / cr, 0.0, 1.0);
      RegionPoint q;
      q.p = {0.5 * (a0.x + t * dax + b0.x + u * dbx), 0.5 * (a0.y + t * day + b0.y + u * dby)};
      q.fa = region_a;
      q.fb = region_b;
      poly.push_back(q);
    } else {
      // Parameters of B's ends along A's segment.
      const double inv = 1.0 / (la * la);
      double tb0 = ((b0.x - a0.x) * dax + (b0.y - a0.y) * day) * inv;
      double tb1 = ((b1.x - a0.x) * dax + (b1.y - a0.y) * day) * inv;
      int hb0 = 0, hb1 = 1;
      if (tb0 > tb1) { std::swap(tb0, tb1); std::swap(hb0, hb1); }
      const RegionPoint lo = tb0 > 0.0 ? b_vertex(hb0) : a_vertex(0);
      const RegionPoint hi = tb1 < 1.0 ? b_vertex(hb1) : a_vertex(1);
      if (std::min(tb1, 1.0) >= std::max(tb0, 0.0) - eps1 / la) {
        poly.push_back(lo);
        poly.push_back(hi);
      }
    }
  } else if (ma == 2 || mb == 2) {
    // Segment clipped by the other side's polygon (Cyrus & Beck 1978 parametric form).
    const bool seg_is_a = ma == 2;
    const int m = seg_is_a ? mb : ma;
    const Pt2 s0 = seg_is_a ? pt_a(0) : pt_b(0), s1 = seg_is_a ? pt_a(1) : pt_b(1);
    double t_lo = 0.0, t_hi = 1.0;
    int l_lo = -1, l_hi = -1;
    bool empty = false;
    for (int l = 0; l < m && !empty; ++l) {
      const Pt2 e0 = seg_is_a ? pt_b(l) : pt_a(l), e1 = seg_is_a ? pt_b(l + 1) : pt_a(l + 1);
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
      auto end_point = [&](double t, int l, int vertex_h) {
        if (l < 0) return seg_is_a ? a_vertex(vertex_h) : b_vertex(vertex_h);
        RegionPoint q;
        q.p = {s0.x + t * (s1.x - s0.x), s0.y + t * (s1.y - s0.y)};
        q.fa = seg_is_a ? region_a : edge_a(l);
        q.fb = seg_is_a ? edge_b(l) : region_b;
        return q;
      };
      poly.push_back(end_point(t_lo, l_lo, 0));
      poly.push_back(end_point(t_hi, l_hi, 1));
    }
  } else {
    // Polygon on polygon: Sutherland-Hodgman, A's polygon clipped by B's edges, with the
    // edge labels carried along so every output corner knows its features.
    for (int h = 0; h < ma; ++h) {
      RegionPoint q = a_vertex(h);
      q.label = h;
      poly.push_back(q);
    }
    for (int l = 0; l < mb && !poly.empty(); ++l) {
      const Pt2 e0 = pt_b(l), e1 = pt_b(l + 1);
      std::vector<RegionPoint>& nxt = sc.next;
      nxt.clear();
      const int np = static_cast<int>(poly.size());
      for (int k = 0; k < np; ++k) {
        const RegionPoint& cur = poly[static_cast<std::size_t>(k)];
        const RegionPoint& nx = poly[static_cast<std::size_t>((k + 1) % np)];
        const double dc = cross2(e0, e1, cur.p), dn = cross2(e0, e1, nx.p);
        const bool cin = dc >= -eps2, nin = dn >= -eps2;
        auto crossing = [&](int label_out) {
          RegionPoint q;
          const double t = std::clamp(dc / (dc - dn), 0.0, 1.0);
          q.p = {cur.p.x + t * (nx.p.x - cur.p.x), cur.p.y + t * (nx.p.y - cur.p.y)};
          q.label = label_out;
          if (cur.label >= 0) {  // A's edge crosses B's edge l
            q.fa = edge_a(cur.label);
            q.fb = edge_b(l);
          } else {  // along B's edge l' into B's edge l: their common vertex
            const int lp = -1 - cur.label;
            int h = -1;
            if ((lp + 1) % mb == l) h = l;
            else if ((l + 1) % mb == lp) h = lp;
            if (h >= 0) {
              const int lab = q.label;
              q = b_vertex(h);
              q.label = lab;
            } else {
              q.fa = region_a;
              q.fb = region_b;
            }
          }
          return q;
        };
        if (cin) {
          nxt.push_back(cur);
          if (!nin) nxt.push_back(crossing(-1 - l));
        } else if (nin) {
          nxt.push_back(crossing(cur.label));
        }
      }
      poly.swap(nxt);
    }
  }

  // Lift every region point onto both surfaces: gap and midpoint along n.
  std::vector<ContactPoint>& cand = sc.candidates;
  cand.clear();
  for (const RegionPoint& q : poly) {
    bool dup = false;
    for (const ContactPoint& c : cand) {
      const Pt2 p = to2(c.point);
      dup = dup || dist2(p, q.p) <= kSamePoint * L;
    }
    if (dup) continue;
    const Vec3 x0 = to3(q.p);
    const double ta = q.va >= 0 ? n.dot(a.world_vertices[q.va]) : lift_a(sc.faces_a, x0, ha);
    const double tb = q.vb >= 0 ? n.dot(b.world_vertices[q.vb]) : lift_b(sc.faces_b, x0, hb);
    ContactPoint c;
    c.point = x0 + n * (0.5 * (ta + tb));
    c.normal = n;
    c.gap = ta - tb;
    c.feature_a = q.fa;
    c.feature_b = q.fb;
    cand.push_back(c);
  }
  if (cand.empty()) {
    // The band features do not overlap in projection (rounding at a corner): one point
    // between the two supporting vertices.
    ContactPoint c;
    c.point = 0.5 * (a.world_vertices[sa] + b.world_vertices[sb]);
    c.normal = n;
    c.gap = ha - hb;
    c.feature_a = feature_id(FeatureKind::Vertex, sa);
    c.feature_b = feature_id(FeatureKind::Vertex, sb);
    cand.push_back(c);
  }
  // At most 4 points, those in contact first: every point pressed in (gap <= 0), and
  // those within kRegionTouch L of the deepest or of touching. A region tilted by 1e-5
  // over a face is in the band at all its corners, and reducing them all by area could
  // drop the second corner that carries the load for one 3e-5 clear of the other body:
  // a loaded pair of a resting bed then lost a support point every few steps and the
  // bed around it needed 80 sweeps instead of 20 (docs/performance.md).
  double g_min = kInf;
  for (const ContactPoint& c : cand) g_min = std::min(g_min, c.gap);
  reduce_touching_first(cand, std::max(g_min, 0.0) + kRegionTouch * L, out);
}

}  // namespace

double plane_separation(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n) {
  return evaluate_axis(a, b, n).s;
}

CommonPlaneResult find_common_plane(const PolyhedronView& a, const PolyhedronView& b,
                                    CommonPlaneCache& cache) {
  return solve(a, b, cache, kInf);
}

bool collide_polyhedra(const PolyhedronView& a, const PolyhedronView& b, double margin,
                       CommonPlaneCache& cache, ContactManifold& out, CommonPlaneResult* plane) {
  out.count = 0;
  const CommonPlaneResult r = solve(a, b, cache, margin);
  if (plane != nullptr) *plane = r;
  if (r.early_out || r.gap > margin) return false;
  build_manifold(a, b, r.normal, out);
  return out.count > 0;
}

}  // namespace ratchet

// Internals of the Common Plane narrow phase (common_plane.hpp), shared by its files:
//   common_plane_gjk.cpp          GJK distance of separated bodies
//   common_plane_search.cpp       facet search (SAT with pruning) of overlapping bodies
//   common_plane_certificate.cpp  proof that the cached facet is still the best one
//   common_plane_region.cpp       contact region (band features clipped) and manifold
//   common_plane.cpp              the public entry points and the order they run in
// Private: included by those files and their tests only. The helpers that the hot loops
// of several files call are inline here, so that no file pays a call for them.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ratchet/contact/common_plane.hpp"

namespace ratchet::cp_detail {

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
// |edge| sin(angle) <= 1e-10 L (argued in edge_pair_facet below).
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
// Certificate (common_plane_certificate.cpp): directions of D's facets farther than
// kCertFarAngle from the cached facet's normal are bounded by a scan at the step that
// made the certificate; nearer ones by the facet's own geometry at the current step.
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

inline int vertex_count(const PolyhedronView& p) { return static_cast<int>(p.shape->vertices.size()); }

inline double pair_length(const PolyhedronView& a, const PolyhedronView& b) {
  return a.scale * a.shape->bounding_radius + b.scale * b.shape->bounding_radius;
}

// argmin_i n.v_i and argmax_i n.v_i, lowest index on ties.
inline int argmin_dot(const Vec3* v, int count, const Vec3& n, double& h) {
  int best = 0;
  double hb = n.dot(v[0]);
  for (int i = 1; i < count; ++i) {
    const double x = n.dot(v[i]);
    if (x < hb) { hb = x; best = i; }
  }
  h = hb;
  return best;
}
inline int argmax_dot(const Vec3* v, int count, const Vec3& n, double& h) {
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
inline AxisValue evaluate_axis(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n) {
  AxisValue r;
  double ha = 0.0, hb = 0.0;
  r.ia = argmin_dot(a.world_vertices, vertex_count(a), n, ha);
  r.ib = argmax_dot(b.world_vertices, vertex_count(b), n, hb);
  r.s = ha - hb;
  return r;
}

// ---------------------------------------------------------------------------------
// GJK (common_plane_gjk.cpp): the simplex of support-vertex pairs on D = A - B.
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

struct GjkOutcome {
  bool proven_apart = false;  // a plane with s > 0 was found and GJK converged
  bool early_out = false;     // s > cutoff found
  double s = -kInf;           // best lower bound s(n) seen
  Vec3 n = Vec3::UnitZ();     // its direction
  Vec3 v = Vec3::Zero();      // final closest point of the simplex (the link, up to rounding)
  Simplex simplex;            // final simplex (its vertices are the closest features)
  int iterations = 0;
};

// GJK distance from simplex s; stops early once s(n) > cutoff is proven.
GjkOutcome gjk(const PolyhedronView& a, const PolyhedronView& b, Simplex s, double cutoff);

// The exact normal of the final simplex's closest features, if they span one (see
// common_plane_gjk.cpp): false if n is not near-orthogonal to them.
bool polish_normal(const PolyhedronView& a, const PolyhedronView& b, const Simplex& s, const Vec3& n,
                   Vec3& out);

// ---------------------------------------------------------------------------------
// Facet search (common_plane_search.cpp) and the certificate's far scan share the
// candidate, the edge-pair evaluation and the pruning bounds.
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
inline void offer(Candidate& best, double s, const Vec3& n, PlaneFeature kind, int ia, int ib) {
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
inline double inradius(const PolyhedronView& p) {
  const double rho = p.shape->min_face_offset;
  return rho > 0.0 ? p.scale * rho : -p.scale * p.shape->bounding_radius;
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
inline bool edge_pair_facet(const EdgeData& ea, const EdgeData& eb, double& s, Vec3& n) {
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
inline EdgeData edge_data(const PolyhedronView& p, int e) {
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
inline double face_a_value(const PolyhedronView& a, const PolyhedronView& b, int f, Vec3& n) {
  const Vec3 m = a.face_normal(f);
  n = -m;
  double hb = 0.0;
  argmin_dot(b.world_vertices, vertex_count(b), m, hb);
  return hb - a.face_offset(f);
}
// Face axis of B: n = m, s = min_a (m.a) - d_g.
inline double face_b_value(const PolyhedronView& a, const PolyhedronView& b, int g, Vec3& n) {
  n = b.face_normal(g);
  double ha = 0.0;
  argmin_dot(a.world_vertices, vertex_count(a), n, ha);
  return ha - b.face_offset(g);
}

// Can face axis f beat lim? Bound (1) first (already computed), then bound (2) per
// reference vertex until one rules it out.
inline bool face_may_win(SideBounds& sb, int f, double rho, double lim) {
  if (!(sb.centre[static_cast<std::size_t>(f)] - rho > lim)) return false;
  for (int k = 0; k < sb.refs; ++k)
    if (!(sb.value(f, k) > lim)) return false;
  return true;
}

// The k best supports of body q along direction u (largest u.x first, lowest index on
// ties); k = min(kRefVertices, vertex count).
int top_supports(const PolyhedronView& q, const Vec3& u, std::array<int, kRefVertices>& idx);

// Prepares the bounds of body p's face axes (sign: n = sign * outward normal) with the
// other body's reference vertices `refs`, and the faces that may beat lim.
void face_bounds(const PolyhedronView& p, double sign, const Vec3& d, const PolyhedronView& other,
                 const std::array<int, kRefVertices>& refs, int nrefs, double rho, double lim,
                 SideBounds& out);

// Edges of body p whose Gauss arc may hold an axis better than lim.
void active_edges(const PolyhedronView& p, SideBounds& bounds, double rho, double lim,
                  std::vector<EdgeData>& out);

// Raises `best` to the best facet of D (every facet that could beat it is evaluated);
// `best_face` receives the best face axis seen. Returns early once best.s > cutoff.
void sat_search(const PolyhedronView& a, const PolyhedronView& b, Candidate& best, Candidate& best_face,
                double cutoff, CommonPlaneResult& r);

// ---------------------------------------------------------------------------------
// Certificate (common_plane_certificate.cpp).
// ---------------------------------------------------------------------------------

// Makes the certificate of facet F (the SAT's result, s its scanned value <= 0) when
// the pair is certifiable now: the next steps then check it instead of searching.
void make_certificate(const PolyhedronView& a, const PolyhedronView& b, const Candidate& F, double s,
                      PlaneCertificate& cert);

// Does the certificate prove that the start facet F (its scanned value F.s, supports
// av) is what the SAT would return at the current pose?
bool certificate_holds(const PolyhedronView& a, const PolyhedronView& b, const PlaneCertificate& cert,
                       const Candidate& F, const AxisValue& av);

// ---------------------------------------------------------------------------------
// Contact region (common_plane_region.cpp).
// ---------------------------------------------------------------------------------

// The manifold of a pair whose common plane has normal n (from B towards A): the
// corners of the contact region, at most 4.
void build_manifold(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n, ContactManifold& out);

}  // namespace ratchet::cp_detail

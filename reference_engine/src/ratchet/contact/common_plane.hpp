// Narrow phase for two convex polyhedra by the Common Plane (CP) method
// (Cundall 1988; Nezami et al. 2004, 2006; docs/method.md section 3).
//
// Legend (the paper's symbols):
//   n  unit normal of the common plane, from body B towards body A
//   g  signed gap along n: g = max over unit n of  s(n),
//        s(n) = min_{a in A} n.a - max_{b in B} n.b
//      i.e. the distance between the bodies when they are apart (the plane is the
//      perpendicular bisector of the shortest link, Nezami et al. 2006) and minus the
//      penetration depth (minimum translation distance) when they overlap.
//
// s(n) = min_{d in D} n.d on the Minkowski difference D = A - B, so g is the signed
// distance from the origin to the boundary of D. The optimum is found exactly by
//   * overlap (origin in D): the separating-axis test over the facets of D, i.e. the
//     face normals of A and B and the edge pairs whose Gauss-map arcs cross
//     (Gregorius, GDC 2013, "The Separating Axis Test between Convex Polyhedra").
//     Candidate axes are pruned with a rigorous bound (common_plane_search.cpp), and the
//     bound is tight when a warm start supplies a near-optimal axis;
//   * separation (origin outside D): GJK distance (Gilbert, Johnson & Keerthi 1988,
//     IEEE J. Robotics Autom. 4(2)) with Johnson's sub-algorithm in the Voronoi-region
//     form of Ericson 2005 (Real-Time Collision Detection, s. 5.1), warm started from
//     the previous step's simplex.
// The returned gap is always s(n) evaluated at the returned normal over the world
// vertices, so it is a value the plane actually achieves (never above the optimum).
#pragma once

#include <array>
#include <cstdint>

#include "ratchet/contact/contact_point.hpp"
#include "ratchet/contact/polyhedron_view.hpp"

namespace ratchet {

// What the cached plane was made of, so the next step can re-evaluate that feature
// at the new poses instead of starting from the centre line.
enum class PlaneFeature : std::int8_t {
  None = 0,
  FaceA,     // index_a: face of A (n = -its outward normal)
  FaceB,     // index_b: face of B (n = its outward normal)
  EdgeEdge,  // index_a, index_b: edges whose Gauss-map arcs cross
  Simplex,   // separated: GJK simplex of support-vertex pairs
  Axis       // any other direction (n itself)
};

// A proof, made at the step that last searched, that the cached facet of D is still the
// best one at a later pose (common_plane_certificate.cpp): the pose it was made at
// (B in A's frame), what the search bounded there, and the features that may span a
// facet next to it. It never changes a result: a certified step returns what the
// search would return, bit for bit; it only saves the search. Not written to state
// files: a restart without it searches once and makes a new one.
struct PlaneCertificate {
  static constexpr int kFaces = 4;   // per body, at most
  static constexpr int kEdges = 12;  // per body, at most
  bool valid = false;
  std::int8_t faces_a = 0, faces_b = 0, edges_a = 0, edges_b = 0;  // counts of the lists below
  Mat3 rotation = Mat3::Zero();   // R_A^T R_B
  Vec3 offset = Vec3::Zero();     // R_A^T (c_B - c_A)
  double scale_a = 1.0, scale_b = 1.0;
  Vec3 normal_a = Vec3::Zero();   // outward normal of the facet of D = A - B, A's frame
  double far_bound = 0.0;         // s of every facet far from that normal was below this
  std::array<std::int16_t, kFaces> face_a{}, face_b{};  // faces near the facet normal
  std::array<std::int16_t, kEdges> edge_a{}, edge_b{};  // edges nearly orthogonal to it
};

struct CommonPlaneCache {
  Vec3 normal = Vec3::Zero();  // last plane normal, from B towards A
  bool valid = false;
  PlaneFeature kind = PlaneFeature::None;
  int index_a = -1;
  int index_b = -1;
  int simplex_count = 0;                           // GJK simplex size (1..3 when apart)
  std::array<std::array<int, 2>, 4> simplex{};     // (vertex of A, vertex of B) pairs
  PlaneCertificate certificate;                    // for a facet of overlapping bodies
};

struct CommonPlaneResult {
  Vec3 normal = Vec3::UnitZ();  // from B towards A
  double gap = 0.0;             // signed gap g along normal
  bool separated = false;       // g > 0 proven by a separating plane
  bool early_out = false;       // collide_polyhedra only: g > margin proven, g is a lower bound
  PlaneFeature feature = PlaneFeature::None;
  int gjk_iterations = 0;       // support mappings of GJK
  int sat_axes = 0;             // candidate axes evaluated (face and edge-pair axes, start axis)
  int sat_edge_pairs = 0;       // edge pairs put through the Gauss-map test
  bool certified = false;       // the cached facet's certificate held: no search ran
  // One number for "how much search": what warm starting is meant to reduce.
  int iterations() const { return gjk_iterations + sat_axes; }
};

// s(n) = min_{a in A} n.a - max_{b in B} n.b over the world vertices: the gap that the
// plane with normal n achieves (a lower bound of the optimum for every n).
double plane_separation(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n);

// Exact common plane. The cache is read (if valid) and updated.
CommonPlaneResult find_common_plane(const PolyhedronView& a, const PolyhedronView& b,
                                    CommonPlaneCache& cache);

// Contact manifold: empty (count 0, returns false) when g > margin; otherwise the
// corners of the contact region, at most 4 (see common_plane_region.cpp for the band
// and the clipping). `plane`, if given, receives the common plane found.
bool collide_polyhedra(const PolyhedronView& a, const PolyhedronView& b, double margin,
                       CommonPlaneCache& cache, ContactManifold& out,
                       CommonPlaneResult* plane = nullptr);

}  // namespace ratchet

// Brute-force oracle for the common plane (tests only): no pruning, no warm start, no
// iteration, so it shares no failure mode with the engine's search.
//
// Overlap: the separating-axis test over ALL face normals of both bodies and ALL
// edge-edge cross products (both signs), each axis evaluated by full support scans.
// The facets of D = A - B have exactly these normals, so for overlapping bodies the
// best axis is the exact minimum translation distance.
//
// Separation: the SAT is then only a lower bound of the distance. Its axes are facet
// normals of D, but when the shortest link ends at a vertex or an edge of D (vertex-
// vertex, vertex-edge, or an edge-edge pair that is not a facet of D), the direction
// of the link is not among them, and the best facet plane lies strictly closer than the
// true distance (two spheres-like cornered bodies touching corner to corner are the
// plain example). So for separated pairs the oracle also computes the exact distance
// over all feature pairs: every vertex against every (fan) triangle of the other body,
// both ways, and every edge against every edge.
#pragma once

#include "ratchet/contact/polyhedron_view.hpp"

namespace ratchet::test {

struct OracleResult {
  Vec3 normal = Vec3::UnitZ();  // from B towards A
  double gap = 0.0;             // signed: distance if apart, -depth if overlapping
  bool separated = false;       // the SAT found an axis with s > 0
  double sat_gap = 0.0;         // best SAT value (equals gap when overlapping)
  // Best SAT value among axes more than tie_angle away from the SAT optimum's axis:
  // close to sat_gap means the optimum is degenerate (several directions achieve it).
  double runner_up = 0.0;
};

// s(n) = min_a n.a - max_b n.b by full scans of the world vertices.
double oracle_separation(const PolyhedronView& a, const PolyhedronView& b, const Vec3& n);

OracleResult oracle_common_plane(const PolyhedronView& a, const PolyhedronView& b,
                                 double tie_angle = 1e-6);

}  // namespace ratchet::test

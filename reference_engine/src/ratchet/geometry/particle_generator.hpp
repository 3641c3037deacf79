// The paper's particle generator (Iliev et al., section 2; after Iliev 2018/2019):
// vertices placed at random on the surface of an ellipsoid with normalised axes
// (a_e, b_e, c_e) = (1, 0.95, 0.9), scaled so that the largest semi-axis is r,
// with r uniform in [r_min, r_max].
#pragma once

#include <vector>

#include "ratchet/core/random.hpp"
#include "ratchet/geometry/convex_polyhedron.hpp"

namespace ratchet {

struct EllipsoidParticleSpec {
  int vertices = 20;                  // points on the ellipsoid surface (hull may keep fewer)
  Vec3 axes = Vec3(1.0, 0.95, 0.9);   // normalised ellipsoid axes
  double radius_min = 0.5;
  double radius_max = 1.0;
};

// One particle: hull of `spec.vertices` random surface points of the ellipsoid with
// largest semi-axis r (r drawn from the range). Consumes random numbers from rng in
// a fixed order (r, then two draws per vertex), so the sequence of particles is fixed
// by the seed. The body frame is centred on the hull's centroid, not the ellipsoid's
// centre, so shape.bounding_radius may exceed r slightly (by at most |centroid|).
//
// Slivers are drawn again: a hull whose inradius about its centroid is below
// kMinInradius r (a plate, possible with few vertices) is discarded and the whole
// particle drawn again from the following numbers, at most kMaxRedraws times
// (then std::invalid_argument); *redrawn, if given, is increased by the redraws. The
// paper's 20-vertex hulls have an inradius near 0.7 r and are never redrawn.
constexpr double kMinInradius = 0.05;
constexpr int kMaxRedraws = 100;
PolyhedronBuild generate_ellipsoid_particle(const EllipsoidParticleSpec& spec, Rng& rng,
                                            double* radius_out = nullptr, int* redrawn = nullptr);

}  // namespace ratchet

// Narrow phase for the pair types with a closed form: sphere-sphere, sphere-plane,
// polyhedron-plane and sphere-polyhedron. Polyhedron-polyhedron is the Common Plane
// method (common_plane.hpp). Conventions of contact_point.hpp: A is the first
// argument, the normal points from B to A, the gap is negative for overlap. Every
// function returns false (and leaves `out` empty) when the gap exceeds `margin`.
#pragma once

#include "ratchet/contact/contact_point.hpp"
#include "ratchet/contact/polyhedron_view.hpp"

namespace ratchet {

bool collide_sphere_sphere(const Vec3& ca, double ra, const Vec3& cb, double rb, double margin,
                           ContactManifold& out);

// Plane {x : n . (x - p) = 0}, bodies kept on the side n points to.
bool collide_sphere_plane(const Vec3& c, double r, const Vec3& n, const Vec3& p, double margin,
                          ContactManifold& out);

// Every vertex closer than margin is a candidate. More than 4 are reduced to 4: the
// vertices touching the plane (within 1e-3 r of the lowest) first, a face lying on the
// plane to 4 corner points (manifold_reduction.hpp), then the nearest of the others.
bool collide_polyhedron_plane(const PolyhedronView& a, const Vec3& n, const Vec3& p, double margin,
                              ContactManifold& out);

// Sphere A against polyhedron B: closest point of B to the sphere centre
// (triangle regions, Ericson 2005, Real-Time Collision Detection, s. 5.1.5), or the
// face of least penetration when the centre is inside B.
bool collide_sphere_polyhedron(const Vec3& c, double r, const PolyhedronView& b, double margin,
                               ContactManifold& out);

// Closest point to p on triangle (a, b, c) (Ericson 2005, s. 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace ratchet

// Collision dispatch: one table from (shape kind, shape kind) to the narrow-phase
// function of that pair type, one from shape kind to the body-against-wall function
// (as Box2D's s_registers and MuJoCo's mjCOLLISIONFUNC), and one from shape kind to how
// a body of that kind is placed for the narrow phase, all sized by ShapeKind::Count. The
// step calls only place_collision_body, collide_pair and collide_wall; adding a contact
// type means a new function and one add_pair line in collide.cpp, which registers it
// for both orders of the pair; a table left incomplete does not compile.
#pragma once

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/contact_point.hpp"
#include "ratchet/contact/polyhedron_view.hpp"
#include "ratchet/scene/scene.hpp"

namespace ratchet {

// One body placed for this step, as the narrow phase sees it.
struct CollisionBody {
  ShapeKind kind = ShapeKind::Sphere;
  Vec3 center = Vec3::Zero();
  double radius = 0.0;   // sphere radius at the current scale (spheres only)
  PolyhedronView poly;   // placed shape (polyhedra only)
};

// Number of world vertices the body's shape places each step (0 for a sphere).
int placed_vertex_count(const SceneDef& scene, const BodyDef& body);

// Body `body` at centre x, rotation R (body -> world) and thermal scale sc, as its kind
// fills a CollisionBody; a kind that places vertices writes its placed_vertex_count of
// them to `vertices` (unused otherwise), which the result points into.
CollisionBody place_collision_body(const SceneDef& scene, const BodyDef& body, const Vec3& x, const Mat3& R,
                                   double sc, Vec3* vertices);

// Whether a pair's manifold may be kept across steps (contact/manifold_reuse.hpp): the
// replay is that of polyhedron pairs.
inline bool manifold_reusable(const CollisionBody& a, const CollisionBody& b) {
  return a.kind == ShapeKind::Polyhedron && b.kind == ShapeKind::Polyhedron;
}

// Body pair A, B (the pair's order: normal from B to A). `cache` is the common plane
// kept for the pair; only polyhedron pairs read and write it.
void collide_pair(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache& cache,
                  ContactManifold& out);

// Body against the wall plane {x : n . (x - p) = 0}.
void collide_wall(const CollisionBody& a, const Vec3& n, const Vec3& p, double margin, ContactManifold& out);

}  // namespace ratchet

#include "ratchet/contact/collide.hpp"

#include <array>
#include <utility>

#include "ratchet/contact/narrow_phase.hpp"

namespace ratchet {

namespace {

constexpr int kKinds = 2;  // ShapeKind::Sphere, ShapeKind::Polyhedron

using PairFn = void (*)(const CollisionBody&, const CollisionBody&, double, CommonPlaneCache&, ContactManifold&);
using WallFn = void (*)(const CollisionBody&, const Vec3&, const Vec3&, double, ContactManifold&);

void sphere_sphere(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache&,
                   ContactManifold& m) {
  collide_sphere_sphere(a.center, a.radius, b.center, b.radius, margin, m);
}

void sphere_polyhedron(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache&,
                       ContactManifold& m) {
  collide_sphere_polyhedron(a.center, a.radius, b.poly, margin, m);
}

// Solved as (sphere, polyhedron), then flipped to the pair's A -> B convention.
void polyhedron_sphere(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache&,
                       ContactManifold& m) {
  collide_sphere_polyhedron(b.center, b.radius, a.poly, margin, m);
  for (int c = 0; c < m.count; ++c) {
    ContactPoint& p = m.points[static_cast<std::size_t>(c)];
    p.normal = -p.normal;
    std::swap(p.feature_a, p.feature_b);
  }
}

void polyhedron_polyhedron(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache& cache,
                           ContactManifold& m) {
  collide_polyhedra(a.poly, b.poly, margin, cache, m);
}

void sphere_wall(const CollisionBody& a, const Vec3& n, const Vec3& p, double margin, ContactManifold& m) {
  collide_sphere_plane(a.center, a.radius, n, p, margin, m);
}

void polyhedron_wall(const CollisionBody& a, const Vec3& n, const Vec3& p, double margin, ContactManifold& m) {
  collide_polyhedron_plane(a.poly, n, p, margin, m);
}

// [kind of A][kind of B], in the order of ShapeKind.
constexpr std::array<std::array<PairFn, kKinds>, kKinds> kPairTable = {{
    {{sphere_sphere, sphere_polyhedron}},
    {{polyhedron_sphere, polyhedron_polyhedron}},
}};
constexpr std::array<WallFn, kKinds> kWallTable = {{sphere_wall, polyhedron_wall}};

int index(ShapeKind k) { return static_cast<int>(k); }

}  // namespace

int placed_vertex_count(const SceneDef& scene, const BodyDef& body) {
  return body.shape >= 0 ? static_cast<int>(scene.shapes[static_cast<std::size_t>(body.shape)].vertices.size()) : 0;
}

void collide_pair(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache& cache,
                  ContactManifold& out) {
  kPairTable[static_cast<std::size_t>(index(a.kind))][static_cast<std::size_t>(index(b.kind))](a, b, margin, cache,
                                                                                              out);
}

void collide_wall(const CollisionBody& a, const Vec3& n, const Vec3& p, double margin, ContactManifold& out) {
  kWallTable[static_cast<std::size_t>(index(a.kind))](a, n, p, margin, out);
}

}  // namespace ratchet

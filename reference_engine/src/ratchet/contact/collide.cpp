#include "ratchet/contact/collide.hpp"

#include <array>
#include <utility>

#include "ratchet/contact/narrow_phase.hpp"

namespace ratchet {

namespace {

constexpr std::size_t kKinds = static_cast<std::size_t>(ShapeKind::Count);

using PairFn = void (*)(const CollisionBody&, const CollisionBody&, double, CommonPlaneCache&, ContactManifold&);
using WallFn = void (*)(const CollisionBody&, const Vec3&, const Vec3&, double, ContactManifold&);
// Fills the kind's part of c, whose kind and center are set (place_collision_body).
using PlaceFn = void (*)(const SceneDef&, const BodyDef&, const Mat3&, double, Vec3*, CollisionBody&);

void sphere_body(const SceneDef&, const BodyDef& body, const Mat3&, double sc, Vec3*, CollisionBody& c) {
  c.radius = body.radius * sc;
}

void polyhedron_body(const SceneDef& scene, const BodyDef& body, const Mat3& R, double sc, Vec3* vertices,
                     CollisionBody& c) {
  const ConvexPolyhedron& shape = scene.shapes[static_cast<std::size_t>(body.shape)];
  for (std::size_t k = 0; k < shape.vertices.size(); ++k) vertices[k] = c.center + sc * (R * shape.vertices[k]);
  c.poly.shape = &shape;
  c.poly.world_vertices = vertices;
  c.poly.center = c.center;
  c.poly.R = R;
  c.poly.scale = sc;
}

void sphere_sphere(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache&,
                   ContactManifold& m) {
  collide_sphere_sphere(a.center, a.radius, b.center, b.radius, margin, m);
}

void sphere_polyhedron(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache&,
                       ContactManifold& m) {
  collide_sphere_polyhedron(a.center, a.radius, b.poly, margin, m);
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

// F for the pair in the other order: solved as (B, A), then turned to the pair's A -> B
// convention (normals reversed, features swapped).
template <PairFn F>
void flipped(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache& cache,
             ContactManifold& m) {
  F(b, a, margin, cache, m);
  for (int c = 0; c < m.count; ++c) {
    ContactPoint& p = m.points[static_cast<std::size_t>(c)];
    p.normal = -p.normal;
    std::swap(p.feature_a, p.feature_b);
  }
}

constexpr std::size_t index(ShapeKind k) { return static_cast<std::size_t>(k); }

struct Tables {
  std::array<std::array<PairFn, kKinds>, kKinds> pair{};  // [kind of A][kind of B]
  std::array<WallFn, kKinds> wall{};
  std::array<PlaceFn, kKinds> place{};
};

// One function per unordered pair of kinds, registered for both orders (as Box2D's
// b2AddType).
template <PairFn F>
constexpr void add_pair(Tables& t, ShapeKind a, ShapeKind b) {
  t.pair[index(a)][index(b)] = F;
  if (a != b) t.pair[index(b)][index(a)] = flipped<F>;
}

constexpr Tables make_tables() {
  Tables t;
  add_pair<sphere_sphere>(t, ShapeKind::Sphere, ShapeKind::Sphere);
  add_pair<sphere_polyhedron>(t, ShapeKind::Sphere, ShapeKind::Polyhedron);
  add_pair<polyhedron_polyhedron>(t, ShapeKind::Polyhedron, ShapeKind::Polyhedron);
  t.wall[index(ShapeKind::Sphere)] = sphere_wall;
  t.wall[index(ShapeKind::Polyhedron)] = polyhedron_wall;
  t.place[index(ShapeKind::Sphere)] = sphere_body;
  t.place[index(ShapeKind::Polyhedron)] = polyhedron_body;
  return t;
}

constexpr Tables kTables = make_tables();

// A kind added to ShapeKind without its functions fails here, not in a run.
constexpr bool complete(const Tables& t) {
  for (std::size_t a = 0; a < kKinds; ++a) {
    if (t.wall[a] == nullptr || t.place[a] == nullptr) return false;
    for (std::size_t b = 0; b < kKinds; ++b)
      if (t.pair[a][b] == nullptr) return false;
  }
  return true;
}
static_assert(complete(kTables),
              "every pair of shape kinds, every kind against a wall and every kind's placing needs a function");

}  // namespace

int placed_vertex_count(const SceneDef& scene, const BodyDef& body) {
  return body.shape >= 0 ? static_cast<int>(scene.shapes[static_cast<std::size_t>(body.shape)].vertices.size()) : 0;
}

CollisionBody place_collision_body(const SceneDef& scene, const BodyDef& body, const Vec3& x, const Mat3& R,
                                   double sc, Vec3* vertices) {
  CollisionBody c;
  c.kind = body.kind;
  c.center = x;
  kTables.place[index(body.kind)](scene, body, R, sc, vertices, c);
  return c;
}

void collide_pair(const CollisionBody& a, const CollisionBody& b, double margin, CommonPlaneCache& cache,
                  ContactManifold& out) {
  kTables.pair[index(a.kind)][index(b.kind)](a, b, margin, cache, out);
}

void collide_wall(const CollisionBody& a, const Vec3& n, const Vec3& p, double margin, ContactManifold& out) {
  kTables.wall[index(a.kind)](a, n, p, margin, out);
}

}  // namespace ratchet

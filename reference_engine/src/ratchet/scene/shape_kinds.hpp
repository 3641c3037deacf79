// What the engine outside contact/ asks of a shape kind, answered by the kind itself:
// its name and fields in bodies.json, and a body of that kind placed in the world (the
// points whose convex hull it is, its top, how a VTK file draws it, its volume). Each
// kind answers in its own file (sphere_kind.cpp, polyhedron_kind.cpp); observe/ and
// io/ ask through shape_kind() and never look at ShapeKind themselves.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/scene/scene.hpp"

namespace ratchet {

// A body as a state places it, at its thermal scale.
struct PlacedBody {
  // Points whose convex hull is the body: a polyhedron's world vertices; for a sphere
  // its 6 axis points and 8 diagonal surface points (an inscribed approximation).
  std::vector<Vec3> points;
  double top = 0.0;            // highest z: the sphere's top, the highest vertex
  // How a VTK file draws it: sphere_radius > 0, a glyph of that radius at the centre
  // (a Verts cell); else its faces (indices into points, Polys cells).
  double sphere_radius = 0.0;
  const std::vector<std::vector<int>>* faces = nullptr;
  double volume = 0.0;         // at the thermal scale
};

class ShapeKindFacts {
 public:
  virtual ~ShapeKindFacts() = default;
  // The kind's name in bodies.json ("kind").
  virtual const char* name() const = 0;
  // bodies.json: the body's shape fields "radius" and "shape", in that order (null where
  // the kind has none; docs/output-format.md, "Bodies and shapes").
  virtual void write_fields(const BodyDef& b, nlohmann::ordered_json& j) const = 0;
  // Body b at centre x, orientation q and thermal scale sc into `out` (its storage is
  // reused).
  virtual void place(const SceneDef& scene, const BodyDef& b, const Vec3& x, const Quat& q, double sc,
                     PlacedBody& out) const = 0;
  // PlacedBody::top of that placement alone (the same bits): the bed height is taken at
  // every step (the pressure peaks), where placing every point cost 3 % of the step.
  virtual double top(const SceneDef& scene, const BodyDef& b, const Vec3& x, const Quat& q, double sc) const = 0;
};

// The facts of kind k (one entry per ShapeKind, shape_kinds.cpp).
const ShapeKindFacts& shape_kind(ShapeKind k);

// The kinds' own files.
const ShapeKindFacts& sphere_kind();
const ShapeKindFacts& polyhedron_kind();

}  // namespace ratchet

// The polyhedron's facts (scene/shape_kinds.hpp): an index into SceneDef::shapes, no
// radius; placed as its world vertices and drawn as its faces.
#include <algorithm>
#include <cmath>

#include "ratchet/scene/shape_kinds.hpp"

namespace ratchet {

namespace {

class PolyhedronKind final : public ShapeKindFacts {
 public:
  const char* name() const override { return "polyhedron"; }

  void write_fields(const BodyDef& b, nlohmann::ordered_json& j) const override {
    j["radius"] = nullptr;
    j["shape"] = b.shape;
  }

  void place(const SceneDef& scene, const BodyDef& b, const Vec3& x, const Quat& q, double sc,
             PlacedBody& out) const override {
    const ConvexPolyhedron& shape = scene.shapes[static_cast<std::size_t>(b.shape)];
    const Mat3 R = q.toRotationMatrix();
    out.points.clear();
    for (const Vec3& v : shape.vertices) out.points.push_back(x + sc * (R * v));
    out.top = top(scene, b, x, q, sc);
    out.sphere_radius = 0.0;
    out.faces = &shape.faces;
    out.volume = shape.volume * sc * sc * sc;
  }

  double top(const SceneDef& scene, const BodyDef& b, const Vec3& x, const Quat& q, double sc) const override {
    const ConvexPolyhedron& shape = scene.shapes[static_cast<std::size_t>(b.shape)];
    const Mat3 R = q.toRotationMatrix();
    double t = -HUGE_VAL;
    // Not the placed points' z: Eigen rounds (R v).z and R.row(2).dot(v) differently,
    // and bed_height has always been the latter.
    for (const Vec3& v : shape.vertices) t = std::max(t, x.z() + sc * R.row(2).dot(v));
    return t;
  }
};

}  // namespace

const ShapeKindFacts& polyhedron_kind() {
  static const PolyhedronKind kind;
  return kind;
}

}  // namespace ratchet

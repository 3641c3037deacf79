// The sphere's facts (scene/shape_kinds.hpp): a radius, no shape; placed as 14 surface
// points and drawn as a glyph at its centre.
#include <cmath>

#include "ratchet/scene/shape_kinds.hpp"

namespace ratchet {

namespace {

class SphereKind final : public ShapeKindFacts {
 public:
  const char* name() const override { return "sphere"; }

  void write_fields(const BodyDef& b, nlohmann::ordered_json& j) const override {
    j["radius"] = b.radius;
    j["shape"] = nullptr;
  }

  void place(const SceneDef& scene, const BodyDef& b, const Vec3& x, const Quat& q, double sc,
             PlacedBody& out) const override {
    const double r = b.radius * sc;
    const double d = 1.0 / std::sqrt(3.0);
    out.points.clear();
    for (int a = 0; a < 3; ++a)
      for (double sign : {-1.0, 1.0}) out.points.push_back(x + sign * r * Vec3::Unit(a));
    for (double sx : {-d, d})
      for (double sy : {-d, d})
        for (double sz : {-d, d}) out.points.push_back(x + r * Vec3(sx, sy, sz));
    out.top = top(scene, b, x, q, sc);
    out.sphere_radius = r;
    out.faces = nullptr;
    out.volume = 4.0 / 3.0 * M_PI * r * r * r;
  }

  double top(const SceneDef&, const BodyDef& b, const Vec3& x, const Quat&, double sc) const override {
    return x.z() + b.radius * sc;
  }
};

}  // namespace

const ShapeKindFacts& sphere_kind() {
  static const SphereKind kind;
  return kind;
}

}  // namespace ratchet

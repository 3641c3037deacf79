#include "ratchet/io/bodies_file.hpp"

#include <stdexcept>

#include "ratchet/io/atomic_file.hpp"
#include "ratchet/scene/shape_kinds.hpp"

namespace ratchet {

namespace {

using ojson = nlohmann::ordered_json;

ojson vec(const Vec3& v) { return ojson::array({v.x(), v.y(), v.z()}); }

}  // namespace

ojson bodies_document(const SceneDef& scene, const State& state) {
  const std::size_t n = scene.bodies.size();
  if (state.x.size() != n || state.v.size() != n || state.w.size() != n || state.q.size() != n)
    throw std::invalid_argument("bodies_document: the state has " + std::to_string(state.x.size()) +
                                " bodies, the scene " + std::to_string(n));
  ojson doc;
  doc["format"] = kBodiesFileFormat;
  doc["version"] = kBodiesFileVersion;
  doc["engine"] = {{"name", "ratchet"}, {"version", RATCHET_VERSION}, {"build_type", RATCHET_BUILD_TYPE}};
  doc["scene_name"] = scene.name;
  doc["scene_file"] = scene.source;
  doc["scene_hash"] = scene.hash;
  doc["seed"] = scene.seed;
  doc["density"] = scene.materials.density;
  doc["step"] = state.step;
  doc["t"] = state.t;
  doc["s_p"] = state.s_p;
  doc["s_c"] = state.s_c;
  ojson bodies = ojson::array();
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDef& b = scene.bodies[i];
    const ShapeKindFacts& kind = shape_kind(b.kind);
    const Quat& q = state.q[i];
    ojson j;
    j["index"] = i;
    j["kind"] = kind.name();
    kind.write_fields(b, j);
    j["position"] = vec(state.x[i]);
    j["orientation"] = ojson::array({q.w(), q.x(), q.y(), q.z()});
    j["velocity"] = vec(state.v[i]);
    j["angular_velocity"] = vec(state.w[i]);
    j["mass"] = b.mass;
    j["principal_inertia"] = vec(b.principal_inertia);
    j["bounding_radius"] = b.bounding_radius;
    j["fixed"] = b.fixed;
    bodies.push_back(std::move(j));
  }
  doc["bodies"] = std::move(bodies);
  ojson shapes = ojson::array();
  for (std::size_t k = 0; k < scene.shapes.size(); ++k) {
    const ConvexPolyhedron& s = scene.shapes[k];
    ojson j;
    j["index"] = k;
    ojson vs = ojson::array();
    for (const Vec3& v : s.vertices) vs.push_back(vec(v));
    j["vertices"] = std::move(vs);
    j["faces"] = s.faces;
    j["volume"] = s.volume;
    j["principal_inertia_per_density"] = vec(s.principal_inertia);
    j["bounding_radius"] = s.bounding_radius;
    shapes.push_back(std::move(j));
  }
  doc["shapes"] = std::move(shapes);
  return doc;
}

std::string format_bodies_document(const ojson& doc) {
  std::string out = "{\n";
  std::size_t k = 0;
  for (auto it = doc.begin(); it != doc.end(); ++it, ++k) {
    out += "  " + ojson(it.key()).dump() + ": ";
    const ojson& v = it.value();
    if (v.is_array() && !v.empty() && v.front().is_object()) {  // bodies, shapes: one per line
      out += "[\n";
      for (std::size_t i = 0; i < v.size(); ++i) out += "    " + v[i].dump() + (i + 1 < v.size() ? ",\n" : "\n");
      out += "  ]";
    } else {
      out += v.dump();
    }
    out += k + 1 < doc.size() ? ",\n" : "\n";
  }
  return out + "}\n";
}

void write_bodies_file(const std::string& path, const SceneDef& scene, const State& state) {
  write_file_atomic(path, format_bodies_document(bodies_document(scene, state)));
}

}  // namespace ratchet

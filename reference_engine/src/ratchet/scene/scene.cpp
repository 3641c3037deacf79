#include "ratchet/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "ratchet/core/random.hpp"
#include "ratchet/geometry/particle_generator.hpp"

namespace ratchet {

using nlohmann::json;

namespace {

// Optimal string alignment distance (a transposition counts as one edit): how far a
// mistyped field name is from a known one.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t k = 0; k <= b.size(); ++k) d[0][k] = k;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t k = 1; k <= b.size(); ++k) {
      const std::size_t cost = a[i - 1] == b[k - 1] ? 0 : 1;
      d[i][k] = std::min({d[i - 1][k] + 1, d[i][k - 1] + 1, d[i - 1][k - 1] + cost});
      if (i > 1 && k > 1 && a[i - 1] == b[k - 2] && a[i - 2] == b[k - 1]) d[i][k] = std::min(d[i][k], d[i - 2][k - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The known name closest to `unknown`, or "" when none is close enough to be a typo
// (at most 2 edits, and at most a third of the name).
std::string closest_name(const std::string& unknown, std::initializer_list<const char*> known) {
  const std::size_t limit = std::max<std::size_t>(1, std::min<std::size_t>(2, unknown.size() / 3));
  std::string best;
  std::size_t best_d = limit + 1;
  for (const char* k : known) {
    const std::size_t d = edit_distance(unknown, k);
    if (d < best_d) best_d = d, best = k;
  }
  return best;
}

// Reading context: every error names where the value came from (the file, or the
// --set option that put it there), the field (dotted path) and what was expected, and
// shows what was found.
struct Reader {
  std::string source;
  // Where the value of a field came from; empty: always `source`.
  std::function<std::string(const std::string& field)> origin_of;

  std::string where(const std::string& field) const { return origin_of ? origin_of(field) : source; }

  [[noreturn]] void fail(const std::string& field, const std::string& expected,
                         const json* got = nullptr) const {
    std::string msg = where(field) + ": field '" + field + "': expected " + expected;
    if (got != nullptr) {
      std::string shown = got->dump();
      if (shown.size() > 80) shown = shown.substr(0, 77) + "...";
      msg += ", got " + shown;
    }
    throw SceneError(msg);
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  void object(const json& j, const std::string& path,
              std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) fail(path.empty() ? "(top level)" : path, "an object", &j);
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool known = false;
      for (const char* a : allowed) known = known || it.key() == a;
      if (!known) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        const std::string field = join(path, it.key()), near = closest_name(it.key(), allowed);
        throw SceneError(where(field) + ": field '" + field + "': unknown field" +
                         (near.empty() ? "" : ", did you mean '" + join(path, near) + "'?") +
                         " (known fields here: " + list + ")");
      }
    }
  }

  double number(const json& j, const std::string& path, const std::string& key, double def,
                double lo, double hi, bool lo_open, bool hi_open, const std::string& expected) const {
    if (!j.contains(key)) return def;
    const json& v = j.at(key);
    const std::string f = join(path, key);
    if (!v.is_number()) fail(f, expected, &v);
    const double x = v.get<double>();
    const bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    if (!ok) fail(f, expected, &v);
    return x;
  }
  double positive(const json& j, const std::string& path, const std::string& key, double def) const {
    return number(j, path, key, def, 0.0, HUGE_VAL, true, false, "a finite positive number");
  }
  double non_negative(const json& j, const std::string& path, const std::string& key, double def) const {
    return number(j, path, key, def, 0.0, HUGE_VAL, false, false, "a finite number >= 0");
  }
  double finite(const json& j, const std::string& path, const std::string& key, double def) const {
    return number(j, path, key, def, -HUGE_VAL, HUGE_VAL, false, false, "a finite number");
  }
  long long integer(const json& j, const std::string& path, const std::string& key, long long def,
                    long long lo, long long hi) const {
    if (!j.contains(key)) return def;
    const json& v = j.at(key);
    const std::string expected = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!v.is_number_integer()) fail(join(path, key), expected, &v);
    const long long x = v.get<long long>();
    if (x < lo || x > hi) fail(join(path, key), expected, &v);
    return x;
  }
  bool boolean(const json& j, const std::string& path, const std::string& key, bool def) const {
    if (!j.contains(key)) return def;
    const json& v = j.at(key);
    if (!v.is_boolean()) fail(join(path, key), "true or false", &v);
    return v.get<bool>();
  }
  std::string string(const json& j, const std::string& path, const std::string& key,
                     const std::string& def) const {
    if (!j.contains(key)) return def;
    const json& v = j.at(key);
    if (!v.is_string()) fail(join(path, key), "a string", &v);
    return v.get<std::string>();
  }
  Vec3 vec3(const json& v, const std::string& f) const {
    if (!v.is_array() || v.size() != 3) fail(f, "an array of 3 finite numbers", &v);
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
      if (!v[static_cast<std::size_t>(i)].is_number()) fail(f, "an array of 3 finite numbers", &v);
      out[i] = v[static_cast<std::size_t>(i)].get<double>();
      if (!std::isfinite(out[i])) fail(f, "an array of 3 finite numbers", &v);
    }
    return out;
  }
  Vec3 vec3(const json& j, const std::string& path, const std::string& key, const Vec3& def) const {
    return j.contains(key) ? vec3(j.at(key), join(path, key)) : def;
  }
  const json& required(const json& j, const std::string& path, const std::string& key,
                       const std::string& expected) const {
    if (!j.contains(key)) fail(join(path, key), expected + " (the field is required)");
    return j.at(key);
  }
};

void read_effects(const Reader& r, const json& j, Effects& e) {
  r.object(j, "effects", {"gravity", "friction", "rotation", "particle_expansion", "container_expansion"});
  e.gravity = r.boolean(j, "effects", "gravity", e.gravity);
  e.friction = r.boolean(j, "effects", "friction", e.friction);
  e.rotation = r.boolean(j, "effects", "rotation", e.rotation);
  e.particle_expansion = r.boolean(j, "effects", "particle_expansion", e.particle_expansion);
  e.container_expansion = r.boolean(j, "effects", "container_expansion", e.container_expansion);
}

void read_solver(const Reader& r, const json& j, SolverSettings& s) {
  const std::string p = "solver";
  r.object(j, p, {"tolerance", "criterion", "max_iterations", "theta", "p_gap", "warm_start", "contact_margin", "threads",
                  "acceleration", "anderson_depth", "compliance", "manifold_reuse"});
  s.tolerance = r.positive(j, p, "tolerance", s.tolerance);
  if (j.contains("criterion")) {
    const json& c = j.at("criterion");
    if (c == "impulse") s.criterion = Criterion::Impulse;
    else if (c == "velocity") s.criterion = Criterion::Velocity;
    else r.fail(p + ".criterion", "\"impulse\" or \"velocity\"", &c);
  }
  s.max_iterations = static_cast<int>(r.integer(j, p, "max_iterations", s.max_iterations, 1, 100000000));
  if (j.contains("acceleration")) {
    const json& a = j.at("acceleration");
    if (a == "none") s.acceleration = Acceleration::None;
    else if (a == "anderson") s.acceleration = Acceleration::Anderson;
    else r.fail(p + ".acceleration", "\"none\" or \"anderson\"", &a);
  }
  s.anderson_depth = static_cast<int>(r.integer(j, p, "anderson_depth", s.anderson_depth, 1, 50));
  s.theta = r.number(j, p, "theta", s.theta, 0.5, 1.0, false, false, "a number in [0.5, 1]");
  s.p_gap = r.number(j, p, "p_gap", s.p_gap, 0.0, 1.0, true, false, "a number in (0, 1]");
  s.compliance = r.number(j, p, "compliance", s.compliance, 0.0, 1.0, false, false, "a number in [0, 1]");
  s.warm_start = r.boolean(j, p, "warm_start", s.warm_start);
  s.contact_margin = r.positive(j, p, "contact_margin", s.contact_margin);
  // Within the margin, a pair that was out of reach cannot come into contact unseen.
  s.manifold_reuse = r.number(j, p, "manifold_reuse", s.manifold_reuse, 0.0, s.contact_margin, false, false,
                              "a length in [0, solver.contact_margin]");
  s.threads = static_cast<int>(r.integer(j, p, "threads", s.threads, 0, 1024));
}

void read_materials(const Reader& r, const json& j, Materials& m) {
  const std::string p = "materials";
  r.object(j, p, {"friction", "wall_friction", "density"});
  m.friction = r.non_negative(j, p, "friction", m.friction);
  m.wall_friction = r.non_negative(j, p, "wall_friction", m.wall_friction);
  m.density = r.positive(j, p, "density", m.density);
}

void read_thermal(const Reader& r, const json& j, ThermalProtocol& t) {
  const std::string p = "thermal";
  r.object(j, p, {"T0", "T1", "start_time", "heat_time", "hold_time", "cool_time", "cycles", "alpha_p", "alpha_c"});
  t.enabled = true;
  t.T0 = r.finite(j, p, "T0", t.T0);
  t.T1 = r.finite(j, p, "T1", t.T1);
  t.start_time = r.non_negative(j, p, "start_time", t.start_time);
  t.heat_time = r.positive(j, p, "heat_time", t.heat_time > 0 ? t.heat_time : 1.0);
  t.hold_time = r.non_negative(j, p, "hold_time", t.hold_time);
  t.cool_time = r.positive(j, p, "cool_time", t.heat_time);
  t.cycles = static_cast<int>(r.integer(j, p, "cycles", 1, 0, 1000000));
  t.alpha_p = r.finite(j, p, "alpha_p", t.alpha_p);
  t.alpha_c = r.finite(j, p, "alpha_c", t.alpha_c);
  // Scales must stay positive over the whole protocol.
  for (double a : {t.alpha_p, t.alpha_c}) {
    if (1.0 + a * (t.T1 - t.T0) <= 0.0)
      r.fail(a == t.alpha_p ? "thermal.alpha_p" : "thermal.alpha_c",
             "1 + alpha (T1 - T0) > 0 (a scale factor cannot vanish)");
  }
}

// Cone: 16 (segments) planar side walls around the z axis and the floor z = 0.
// Side wall k has its middle at azimuth phi_k = 2 pi k / N, distance r_c from the axis
// at z = 0, and leans outward by theta_c: inward normal
// n_k = (-cos(theta_c) cos(phi_k), -cos(theta_c) sin(phi_k), sin(theta_c)).
void build_cone_walls(ContainerDef& c) {
  const double theta = c.opening_angle_deg * M_PI / 180.0;
  c.walls.clear();
  c.walls.push_back({Vec3::UnitZ(), Vec3::Zero(), WallRole::Bottom, true});
  for (int k = 0; k < c.segments; ++k) {
    const double phi = 2.0 * M_PI * k / c.segments;
    const Vec3 n(-std::cos(theta) * std::cos(phi), -std::cos(theta) * std::sin(phi), std::sin(theta));
    const Vec3 p(c.bottom_radius * std::cos(phi), c.bottom_radius * std::sin(phi), 0.0);
    c.walls.push_back({n, p, WallRole::Side, true});
  }
}

void read_container(const Reader& r, const json& j, ContainerDef& c) {
  const std::string p = "container";
  if (!j.is_object()) r.fail(p, "an object", &j);
  const std::string type = r.string(j, p, "type", "");
  if (type == "cone") {
    r.object(j, p, {"type", "bottom_radius", "opening_angle_deg", "segments", "height"});
    c.type = ContainerDef::Type::Cone;
    c.bottom_radius = r.positive(j, p, "bottom_radius", c.bottom_radius);
    c.opening_angle_deg = r.number(j, p, "opening_angle_deg", c.opening_angle_deg, 0.0, 45.0, false,
                                   false, "an angle in degrees in [0, 45]");
    c.segments = static_cast<int>(r.integer(j, p, "segments", c.segments, 3, 1024));
    c.height = r.positive(j, p, "height", c.height);
    build_cone_walls(c);
  } else if (type == "planes") {
    r.object(j, p, {"type", "planes"});
    c.type = ContainerDef::Type::Planes;
    const json& planes = r.required(j, p, "planes", "a list of {normal, point}");
    if (!planes.is_array() || planes.empty()) r.fail(p + ".planes", "a non-empty list of {normal, point}", &planes);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const std::string f = p + ".planes[" + std::to_string(i) + "]";
      r.object(planes[i], f, {"normal", "point", "expands"});
      WallDef w;
      w.normal = r.vec3(r.required(planes[i], f, "normal", "a vector [x, y, z]"), f + ".normal");
      if (w.normal.norm() < 1e-12) r.fail(f + ".normal", "a non-zero vector", &planes[i]["normal"]);
      w.normal.normalize();
      w.point = r.vec3(r.required(planes[i], f, "point", "a point [x, y, z]"), f + ".point");
      w.expands = r.boolean(planes[i], f, "expands", false);
      w.role = WallRole::Plane;
      c.walls.push_back(w);
    }
  } else {
    r.fail(p + ".type", "\"cone\" or \"planes\"", j.contains("type") ? &j.at("type") : nullptr);
  }
}

void set_sphere_mass(BodyDef& b, double density) {
  b.mass = density * 4.0 / 3.0 * M_PI * b.radius * b.radius * b.radius;
  const double I = 0.4 * b.mass * b.radius * b.radius;  // solid sphere, 2/5 m r^2
  b.principal_inertia = Vec3::Constant(I);
  b.bounding_radius = b.radius;
}

void add_polyhedron_body(SceneDef& s, const PolyhedronBuild& build, BodyDef b) {
  b.kind = ShapeKind::Polyhedron;
  b.shape = static_cast<int>(s.shapes.size());
  b.mass = s.materials.density * build.shape.volume;
  b.principal_inertia = s.materials.density * build.shape.principal_inertia;
  b.bounding_radius = build.shape.bounding_radius;
  s.shapes.push_back(build.shape);
  s.bodies.push_back(b);
}

Quat read_quaternion(const Reader& r, const json& j, const std::string& f) {
  if (!j.is_array() || j.size() != 4) r.fail(f, "a quaternion [w, x, y, z]", &j);
  double q[4];
  for (std::size_t i = 0; i < 4; ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) r.fail(f, "a quaternion [w, x, y, z] of finite numbers", &j);
    q[i] = j[i].get<double>();
  }
  Quat out(q[0], q[1], q[2], q[3]);
  if (out.norm() < 1e-12) r.fail(f, "a non-zero quaternion [w, x, y, z]", &j);
  return out.normalized();
}

void read_listed_bodies(const Reader& r, const json& list, SceneDef& s) {
  if (!list.is_array()) r.fail("particles.bodies", "a list of bodies", &list);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string f = "particles.bodies[" + std::to_string(i) + "]";
    const json& j = list[i];
    r.object(j, f, {"shape", "radius", "half_extents", "vertices", "position", "orientation", "velocity",
                    "angular_velocity", "fixed"});
    BodyDef b;
    b.position = r.vec3(r.required(j, f, "position", "a point [x, y, z]"), f + ".position");
    const Quat q_input = j.contains("orientation") ? read_quaternion(r, j.at("orientation"), f + ".orientation")
                                                  : Quat::Identity();
    b.velocity = r.vec3(j, f, "velocity", Vec3::Zero());
    b.angular_velocity = r.vec3(j, f, "angular_velocity", Vec3::Zero());
    b.fixed = r.boolean(j, f, "fixed", false);
    const std::string shape = r.string(j, f, "shape", "");
    try {
      if (shape == "sphere") {
        b.kind = ShapeKind::Sphere;
        (void)r.required(j, f, "radius", "a finite positive number");
        b.radius = r.positive(j, f, "radius", 0.0);
        b.orientation = q_input;
        set_sphere_mass(b, s.materials.density);
        s.bodies.push_back(b);
      } else if (shape == "box" || shape == "polyhedron") {
        PolyhedronBuild build;
        if (shape == "box") {
          const Vec3 he = r.vec3(r.required(j, f, "half_extents", "[a, b, c] half extents"), f + ".half_extents");
          if (!(he.minCoeff() > 0.0)) r.fail(f + ".half_extents", "three positive half extents", &j.at("half_extents"));
          build = build_box(he, r.where(f + ".half_extents") + ": field '" + f + ".half_extents'");
        } else {
          const json& vs = r.required(j, f, "vertices", "a list of at least 4 points [x, y, z]");
          if (!vs.is_array() || vs.size() < 4) r.fail(f + ".vertices", "a list of at least 4 points [x, y, z]", &vs);
          std::vector<Vec3> pts;
          for (std::size_t k = 0; k < vs.size(); ++k) pts.push_back(r.vec3(vs[k], f + ".vertices[" + std::to_string(k) + "]"));
          build = build_convex_polyhedron(pts, r.where(f + ".vertices") + ": field '" + f + ".vertices'");
        }
        // position is where the solid's centroid goes; orientation rotates the input frame.
        b.orientation = (q_input * Quat(build.rotation)).normalized();
        add_polyhedron_body(s, build, b);
      } else {
        r.fail(f + ".shape", "\"sphere\", \"box\" or \"polyhedron\"", j.contains("shape") ? &j.at("shape") : nullptr);
      }
    } catch (const SceneError&) {
      throw;  // already names its origin and field
    } catch (const std::invalid_argument& e) {
      throw SceneError(std::string(e.what()));
    } catch (const std::runtime_error& e) {  // Qhull failures other than bad input
      throw SceneError(r.where(f) + ": field '" + f + "': " + e.what());
    }
  }
}

// Loose lattice inside the container (or the given region), one site per particle,
// filled layer by layer from the bottom; random orientations from the seed.
std::vector<Vec3> lattice_sites(const Reader& r, const SceneDef& s, const json& gen, double spacing, int count,
                                Rng& rng) {
  Vec3 lo, hi;
  bool in_disk = false;
  double disk_radius = 0.0;
  if (gen.contains("region")) {
    const std::string f = "particles.generate.region";
    r.object(gen.at("region"), f, {"min", "max"});
    lo = r.vec3(r.required(gen.at("region"), f, "min", "a point [x, y, z]"), f + ".min");
    hi = r.vec3(r.required(gen.at("region"), f, "max", "a point [x, y, z]"), f + ".max");
    if (!((hi - lo).minCoeff() > 0.0)) r.fail(f, "min < max in every coordinate", &gen.at("region"));
  } else if (s.container.type == ContainerDef::Type::Cone) {
    in_disk = true;
    disk_radius = s.container.bottom_radius - 0.5 * spacing - 0.04 * spacing;
    lo = Vec3(-disk_radius, -disk_radius, 0.0);
    hi = Vec3(disk_radius, disk_radius, HUGE_VAL);
  } else {
    r.fail("particles.generate.region", "a region {min, max} (required unless the container is a cone)");
  }
  std::vector<Vec3> sites;
  // Breaks the lattice symmetry; with spacing >= 2.3 r_max neighbours stay >= 0.92 *
  // 2.3 r_max = 2.1 r_max apart, which clears bounding radii a few % above r_max.
  const double jitter = 0.04 * spacing;
  // Square lattice in x, y: centred on the axis for a cone (sites within disk_radius of
  // it, so each particle's bounding sphere is inside the bottom polygon), from the
  // corner for a region box.
  const Vec3 origin = in_disk ? Vec3(0.0, 0.0, lo.z()) : Vec3(lo.x() + 0.5 * spacing, lo.y() + 0.5 * spacing, lo.z());
  // Sites per row: a region or cone far wider than the spacing would overflow the
  // indices (and the loop would take forever); no bed needs a million per row.
  const double per_row = (in_disk ? 2.0 * disk_radius : std::max(hi.x() - lo.x(), hi.y() - lo.y())) / spacing;
  if (!(per_row <= 1e6))
    r.fail(in_disk ? "container.bottom_radius" : "particles.generate.region",
           "at most 10^6 lattice sites per row at spacing " + std::to_string(spacing) + " (got " +
               std::to_string(per_row) + ")");
  const int kx_lo = in_disk ? -static_cast<int>(std::floor(disk_radius / spacing)) : 0;
  const int kx_hi = in_disk ? -kx_lo : static_cast<int>(std::floor((hi.x() - lo.x()) / spacing)) - 1;
  const int ky_hi = in_disk ? -kx_lo : static_cast<int>(std::floor((hi.y() - lo.y()) / spacing)) - 1;
  for (int layer = 0; static_cast<int>(sites.size()) < count && layer < 1000000; ++layer) {
    const double z = origin.z() + 0.5 * spacing + layer * spacing;
    if (z + 0.5 * spacing > hi.z()) break;
    for (int ky = kx_lo; ky <= ky_hi && static_cast<int>(sites.size()) < count; ++ky)
      for (int kx = kx_lo; kx <= kx_hi; ++kx) {
        const double x = origin.x() + kx * spacing, y = origin.y() + ky * spacing;
        if (in_disk && std::hypot(x, y) > disk_radius) continue;
        if (static_cast<int>(sites.size()) >= count) break;
        // Named draws: the order of evaluation of function arguments is unspecified in
        // C++; y first is the order of the first engine version (the LIGGGHTS translator
        // takes the bodies from `ratchet bodies`, so it needs no copy of this order).
        const double jy = uniform(rng, -jitter, jitter);
        const double jx = uniform(rng, -jitter, jitter);
        sites.emplace_back(x + jx, y + jy, z);
      }
  }
  if (static_cast<int>(sites.size()) < count)
    r.fail("particles.generate.count", "at most " + std::to_string(sites.size()) +
                                           " particles (that is what fits in the region at lattice spacing " +
                                           std::to_string(spacing) + ")",
           &gen.at("count"));
  return sites;
}

void read_generated(const Reader& r, const json& gen, SceneDef& s, Rng& rng) {
  const std::string p = "particles.generate";
  r.object(gen, p, {"count", "shape", "vertices", "ellipsoid_axes", "radius_range", "region", "spacing"});
  const int count = static_cast<int>(r.integer(gen, p, "count", 0, 0, 10000000));
  const std::string shape = r.string(gen, p, "shape", "polyhedron");
  if (shape != "polyhedron" && shape != "sphere")
    r.fail(p + ".shape", "\"polyhedron\" or \"sphere\"", &gen.at("shape"));
  EllipsoidParticleSpec spec;
  spec.vertices = static_cast<int>(r.integer(gen, p, "vertices", spec.vertices, 4, 10000));
  spec.axes = r.vec3(gen, p, "ellipsoid_axes", spec.axes);
  if (!(spec.axes.minCoeff() > 0.0)) r.fail(p + ".ellipsoid_axes", "three positive axes", &gen.at("ellipsoid_axes"));
  if (gen.contains("radius_range")) {
    const json& rr = gen.at("radius_range");
    if (!rr.is_array() || rr.size() != 2 || !rr[0].is_number() || !rr[1].is_number() ||
        !(rr[0].get<double>() > 0.0) || !(rr[1].get<double>() >= rr[0].get<double>()) ||
        !std::isfinite(rr[1].get<double>()))
      r.fail(p + ".radius_range", "[r_min, r_max] with 0 < r_min <= r_max", &rr);
    spec.radius_min = rr[0].get<double>();
    spec.radius_max = rr[1].get<double>();
  }
  const double spacing = r.number(gen, p, "spacing", 2.5 * spec.radius_max, 2.3 * spec.radius_max, HUGE_VAL,
                                  false, false, "a lattice spacing >= 2.3 r_max (sites must not overlap)");
  // Sites first, then shapes and orientations: the sequence of draws is fixed by the seed.
  const std::vector<Vec3> sites = lattice_sites(r, s, gen, spacing, count, rng);
  for (int i = 0; i < count; ++i) {
    BodyDef b;
    b.position = sites[static_cast<std::size_t>(i)];
    if (shape == "sphere") {
      b.kind = ShapeKind::Sphere;
      b.radius = uniform(rng, spec.radius_min, spec.radius_max);
      set_sphere_mass(b, s.materials.density);
      s.bodies.push_back(b);
    } else {
      PolyhedronBuild build;
      try {
        build = generate_ellipsoid_particle(spec, rng, nullptr, &s.redrawn_particles);
      } catch (const std::invalid_argument& e) {
        r.fail(p + ".vertices", std::string("enough vertices for a solid particle (") + e.what() + ")",
               gen.contains("vertices") ? &gen.at("vertices") : nullptr);
      }
      b.orientation = uniform_rotation(rng);
      add_polyhedron_body(s, build, b);
    }
  }
}

// A list of cycle pairs [[a, b], ...] with 0 <= a < b.
std::vector<std::pair<int, int>> read_windows(const Reader& r, const json& j, const std::string& f) {
  const std::string expected = "a list of cycle windows [[a, b], ...] with integers 0 <= a < b";
  if (!j.is_array() || j.empty()) r.fail(f, expected, &j);
  std::vector<std::pair<int, int>> out;
  for (const json& w : j) {
    if (!w.is_array() || w.size() != 2 || !w[0].is_number_integer() || !w[1].is_number_integer() ||
        w[0].get<int>() < 0 || w[1].get<int>() <= w[0].get<int>())
      r.fail(f, expected, &j);
    out.emplace_back(w[0].get<int>(), w[1].get<int>());
  }
  return out;
}

void read_outputs(const Reader& r, const json& j, SceneDef& s) {
  const std::string p = "outputs";
  r.object(j, p, {"timeseries_every", "bodies_every", "volume", "segment_forces", "cycles", "steady_cycles",
                  "displacement", "wall_profile_bins", "settled_profile_time", "vtk_cycles", "vtk_every", "checkpoint_every",
                  "pressure_window"});
  OutputSettings& o = s.outputs;
  o.timeseries_every = static_cast<int>(r.integer(j, p, "timeseries_every", 1, 1, 1 << 30));
  o.bodies_every = static_cast<int>(r.integer(j, p, "bodies_every", 0, 0, 1 << 30));
  o.volume = r.boolean(j, p, "volume", o.volume);
  o.segment_forces = r.boolean(j, p, "segment_forces", o.segment_forces);
  o.cycles = r.boolean(j, p, "cycles", o.cycles);
  o.wall_profile_bins = static_cast<int>(r.integer(j, p, "wall_profile_bins", 0, 0, 100000));
  o.settled_profile_time = r.non_negative(j, p, "settled_profile_time", 0.0);
  if (o.settled_profile_time > 0.0 && o.wall_profile_bins == 0)
    r.fail(p + ".settled_profile_time", "outputs.wall_profile_bins > 0 as well (the bands of the profile)",
           &j.at("settled_profile_time"));
  o.pressure_window = r.non_negative(j, p, "pressure_window", o.pressure_window);
  if (j.contains("steady_cycles")) {  // inclusive [first, last]
    const json& w = j.at("steady_cycles");
    if (!w.is_array() || w.size() != 2 || !w[0].is_number_integer() || !w[1].is_number_integer() ||
        w[0].get<int>() < 0 || w[1].get<int>() < w[0].get<int>())
      r.fail(p + ".steady_cycles", "[first, last] cycle indices with 0 <= first <= last", &w);
    o.steady_first = w[0].get<int>();
    o.steady_last = w[1].get<int>();
  }
  if (j.contains("displacement")) {
    const std::string f = p + ".displacement";
    const json& d = j.at("displacement");
    r.object(d, f, {"cell", "windows", "stages"});
    o.displacement_cell = r.positive(d, f, "cell", 1.0);
    o.displacement_stages = r.boolean(d, f, "stages", false);
    o.displacement_windows = read_windows(r, r.required(d, f, "windows", "a list of cycle windows"), f + ".windows");
  }
  if (j.contains("vtk_cycles")) {
    const json& v = j.at("vtk_cycles");
    if (!v.is_array()) r.fail(p + ".vtk_cycles", "a list of cycle indices", &v);
    for (const json& k : v) {
      if (!k.is_number_integer() || k.get<int>() < 0) r.fail(p + ".vtk_cycles", "a list of cycle indices >= 0", &v);
      o.vtk_cycles.push_back(k.get<int>());
    }
    // The cycles are those of the thermal protocol: without any, the list would
    // silently write nothing.
    if (!o.vtk_cycles.empty() && !(s.thermal.enabled && s.thermal.cycles > 0))
      r.fail(p + ".vtk_cycles",
             "an empty list in a scene without thermal cycles (a thermal section with cycles > 0 is needed; "
             "outputs.vtk_every writes VTK every N steps in any scene)",
             &v);
  }
  o.vtk_every = static_cast<int>(r.integer(j, p, "vtk_every", 0, 0, 1 << 30));
  o.checkpoint_every = static_cast<int>(r.integer(j, p, "checkpoint_every", kDefaultCheckpointEvery, 0, 1 << 30));
}

// The settle stage (run/packing.hpp): until KE <= ke_ratio x peak, at most max_time.
void read_settle(const Reader& r, const json& j, SceneDef& s) {
  r.object(j, "settle", {"ke_ratio", "max_time"});
  (void)r.required(j, "settle", "ke_ratio", "a number in (0, 1)");
  (void)r.required(j, "settle", "max_time", "a finite positive number (the time allowed to settle)");
  s.settle.enabled = true;
  s.settle.ke_ratio = r.number(j, "settle", "ke_ratio", 0.0, 0.0, 1.0, true, true, "a number in (0, 1)");
  s.settle.max_time = r.positive(j, "settle", "max_time", 0.0);
  if (!s.thermal.enabled)
    r.fail("settle", "a scene with a thermal section too (the thermal protocol starts when the bed has settled)");
}

void read_particles(const Reader& r, const json& j, SceneDef& s) {
  r.object(j, "particles", {"generate", "bodies"});
  Rng rng(s.seed);
  try {
    if (j.contains("generate")) read_generated(r, j.at("generate"), s, rng);
  } catch (const std::invalid_argument& e) {
    throw SceneError(r.where("particles.generate") + ": field 'particles.generate': " + e.what());
  }
  if (j.contains("bodies")) read_listed_bodies(r, j.at("bodies"), s);
  if (s.bodies.empty()) r.fail("particles", "at least one body (generate.count > 0 or a bodies list)");
}

}  // namespace

std::string fnv1a_hex(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a 64-bit offset basis
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;  // FNV 64-bit prime
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

void apply_override(json& scene, const std::string& assignment, const std::string& source) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(source + ": --set '" + assignment + "': expected key.path=value");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  json value = json::parse(text, nullptr, false);
  if (value.is_discarded()) value = text;  // not JSON: a plain string
  json* node = &scene;
  std::stringstream ss(path);
  std::string key;
  while (std::getline(ss, key, '.')) {
    if (key.empty()) throw SceneError(source + ": --set '" + assignment + "': empty key in the path");
    if (node->is_null()) *node = json::object();  // a section the scene leaves to its defaults
    if (!node->is_object()) throw SceneError(source + ": --set '" + assignment + "': '" + key + "' is inside a non-object");
    node = &(*node)[key];
  }
  *node = value;
}

namespace {

// The field's JSON pointer: "a.b[2].c" -> /a/b/2/c; "(top level)" -> the root.
json::json_pointer pointer_of(const std::string& field) {
  std::string ptr;
  if (field != "(top level)")
    for (char c : field) {
      if (c == '.' || c == '[') ptr += '/';
      else if (c == '~') ptr += "~0";
      else if (c == '/') ptr += "~1";
      else if (c != ']') ptr += c;
    }
  return json::json_pointer(ptr.empty() ? "" : "/" + ptr);
}

// "a.b[2]" -> "a.b", "a.b" -> "a", "a" -> "".
std::string parent_of(const std::string& field) {
  const auto cut = field.find_last_of(".[");
  return cut == std::string::npos ? "" : field.substr(0, cut);
}

// True when `inner` is `outer` or a field inside it (dotted path with [i] elements).
bool within(const std::string& inner, const std::string& outer) {
  return inner.size() >= outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
         (inner.size() == outer.size() || inner[outer.size()] == '.' || inner[outer.size()] == '[');
}

// Time steps of `span` at `dt`, refused (naming `field`) below one step and above
// kMaxSteps, where std::llround would leave the range of int64 (undefined behaviour).
constexpr double kMaxSteps = 1e15;  // 1e15 steps of even a single body take decades
std::int64_t step_count(const Reader& r, const std::string& field, double span, double dt, const json* value) {
  const double n = span / dt;
  if (!(n >= 0.5)) r.fail(field, "at least one time step (duration >= dt / 2)", value);
  if (!(n <= kMaxSteps)) r.fail(field, "at most 1e15 time steps (duration / time.dt)", value);
  return static_cast<std::int64_t>(std::llround(n));
}

SceneDef build_scene_with(const json& j, const std::string& source,
                          std::function<std::string(const std::string&)> origin_of) {
  Reader r{source, std::move(origin_of)};
  r.object(j, "", {"name", "seed", "gravity", "time", "solver", "materials", "effects", "container",
                   "particles", "thermal", "outputs", "settle", "description"});
  SceneDef s;
  s.source = source;
  s.name = r.string(j, "", "name", "");
  if (s.name.empty()) r.fail("name", "a non-empty string", j.contains("name") ? &j.at("name") : nullptr);
  s.seed = static_cast<std::uint64_t>(r.integer(j, "", "seed", 1, 0, std::numeric_limits<long long>::max()));
  s.gravity = r.vec3(j, "", "gravity", s.gravity);
  if (j.contains("effects")) read_effects(r, j.at("effects"), s.effects);
  if (j.contains("solver")) read_solver(r, j.at("solver"), s.solver);
  if (j.contains("materials")) read_materials(r, j.at("materials"), s.materials);
  if (j.contains("thermal")) read_thermal(r, j.at("thermal"), s.thermal);
  if (j.contains("container")) read_container(r, j.at("container"), s.container);
  if (j.contains("outputs")) read_outputs(r, j.at("outputs"), s);
  if (j.contains("settle")) read_settle(r, j.at("settle"), s);
  const json& time = r.required(j, "", "time", "an object {dt, duration}");
  r.object(time, "time", {"dt", "duration"});
  s.dt = r.positive(time, "time", "dt", s.dt);
  std::string span_field = "time.duration";  // the field an error about the step count names
  const json* span_value = nullptr;
  if (time.contains("duration")) {
    s.duration = r.positive(time, "time", "duration", 0.0);
    span_value = &time.at("duration");
  } else if (s.thermal.enabled && s.thermal.cycles > 0) {
    s.duration = s.thermal.start_time + s.thermal.cycles * s.thermal.cycle_time();
    span_field = "thermal";  // derived: named by the protocol's fields
  } else {
    r.fail("time.duration", "a positive duration (or a thermal protocol with cycles to derive it from)");
  }
  s.steps = step_count(r, span_field, s.duration, s.dt, span_value);
  if (s.settle.enabled) {
    // Times written in the scene count from the end of the settle stage; until it is
    // known, assume the latest (SettleDef).
    s.settle.rest_time = s.thermal.start_time;
    s.settle.run_time = s.duration;
    s.thermal.start_time = s.settle.max_time + s.settle.rest_time;
    s.duration = s.settle.max_time + s.settle.run_time;
    s.steps = step_count(r, "settle.max_time", s.settle.max_time, s.dt, &j.at("settle").at("max_time")) + s.steps;
  }
  read_particles(r, r.required(j, "", "particles", "an object {generate and/or bodies}"), s);
  s.as_run = j;
  s.hash = fnv1a_hex(j.dump());
  return s;
}

}  // namespace

SceneDef build_scene(const json& j, const std::string& source) { return build_scene_with(j, source, nullptr); }

SceneDef load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  json j = json::parse(in, nullptr, false, /*ignore_comments=*/true);
  if (j.is_discarded()) {
    // Parse again with exceptions on to report where the syntax breaks.
    std::ifstream again(path);
    try {
      const json unused = json::parse(again, nullptr, true, true);
      (void)unused;
    } catch (const json::exception& e) {  // parse_error, or out_of_range for a number beyond a double
      throw SceneError(path + ": not valid JSON: " + e.what());
    }
    throw SceneError(path + ": not valid JSON");
  }
  const json file = j;
  for (const std::string& o : overrides) apply_override(j, o, path);
  // An error in a value that a --set put there names that --set, not the file: the
  // field is the --set's key or inside it, or the file lacks the field and a --set made
  // its outermost missing section (--set settle.max_time=5 makes 'settle').
  const auto origin_of = [&](const std::string& field) -> std::string {
    std::string made = field;  // the outermost section on the way to `field` that the file lacks
    if (!file.contains(pointer_of(field)))
      for (std::string up = parent_of(made); !up.empty() && !file.contains(pointer_of(up)); up = parent_of(up)) made = up;
    else
      made.clear();
    for (auto o = overrides.rbegin(); o != overrides.rend(); ++o) {
      const std::string key = o->substr(0, o->find('='));
      if (within(field, key) || (!made.empty() && within(key, made)))
        return "--set " + *o + " (command-line option, applied to " + path + ")";
    }
    return path;
  };
  return build_scene_with(j, path, origin_of);
}

}  // namespace ratchet

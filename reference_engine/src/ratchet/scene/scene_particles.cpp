// The particles section (docs/scene-format.md, "particles"): the bodies listed one by
// one, and beds generated from the seed (ellipsoid polyhedra or spheres on a jittered
// lattice), with their masses, inertias and shapes.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "ratchet/core/random.hpp"
#include "ratchet/geometry/particle_generator.hpp"
#include "ratchet/scene/scene_detail.hpp"

namespace ratchet::scene_detail {

namespace {

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
  if (out.norm() < kZeroNorm) r.fail(f, "a non-zero quaternion [w, x, y, z]", &j);
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
    r.fill(f, "orientation", json::array({1.0, 0.0, 0.0, 0.0}));
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
  r.fill(p, "radius_range", json::array({spec.radius_min, spec.radius_max}));
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

}  // namespace

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

}  // namespace ratchet::scene_detail

// The sections of a scene besides particles and time (docs/scene-format.md), each
// read into its part of SceneDef.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "ratchet/scene/scene_detail.hpp"
#include "ratchet/solver/nsgs.hpp"  // kMaxAndersonDepth

namespace ratchet::scene_detail {

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
                  "acceleration", "anderson_depth", "compliance", "tangential_law", "manifold_reuse", "method",
                  "stall_fallback", "slide_newton_steps"});
  if (j.contains("method")) {
    const json& m = j.at("method");
    if (m == "nsgs") s.method = SolverMethod::Nsgs;
    else r.fail(p + ".method", "\"nsgs\"", &m);
  }
  s.tolerance = r.positive(j, p, "tolerance", s.tolerance);
  s.criterion = r.choice(j, p, "criterion", s.criterion,
                         {{"impulse", Criterion::Impulse}, {"velocity", Criterion::Velocity}});
  s.max_iterations = static_cast<int>(r.integer(j, p, "max_iterations", s.max_iterations, 1, 100000000));
  s.acceleration = r.choice(j, p, "acceleration", s.acceleration,
                            {{"none", Acceleration::None}, {"anderson", Acceleration::Anderson}});
  s.anderson_depth = static_cast<int>(r.integer(j, p, "anderson_depth", s.anderson_depth, 1, kMaxAndersonDepth));
  s.theta = r.number(j, p, "theta", s.theta, 0.5, 1.0, false, false, "a number in [0.5, 1]");
  s.p_gap = r.number(j, p, "p_gap", s.p_gap, 0.0, 1.0, true, false, "a number in (0, 1]");
  s.compliance = r.number(j, p, "compliance", s.compliance, 0.0, 1.0, false, false, "a number in [0, 1]");
  s.tangential_law = r.choice(j, p, "tangential_law", s.tangential_law,
                              {{"creep", TangentialLaw::Creep}, {"spring", TangentialLaw::Spring}});
  s.stall_fallback = r.choice(j, p, "stall_fallback", s.stall_fallback,
                              {{"plain", StallFallback::Plain}, {"apgd", StallFallback::Apgd}});
  // The gradient method solves the rigid law's convex problems; a compliant solve has
  // its own stall guard (relaxed sweeps).
  if (s.stall_fallback == StallFallback::Apgd && s.compliance > 0.0)
    r.fail(p + ".stall_fallback", "\"plain\" while solver.compliance > 0 (\"apgd\" is for the rigid law)",
           &j.at("stall_fallback"));
  // 0 is the exact local slide; above the Newton cap (30 steps) a budget never binds.
  s.slide_newton_steps = static_cast<int>(r.integer(j, p, "slide_newton_steps", s.slide_newton_steps, 0, 30));
  s.warm_start = r.boolean(j, p, "warm_start", s.warm_start);
  // The spring's load is the contact's kept impulse, which only the warm start finds.
  if (s.tangential_law == TangentialLaw::Spring && !s.warm_start)
    r.fail(p + ".tangential_law", "\"creep\" while solver.warm_start is false (the spring holds the kept impulse)",
           &j.at("tangential_law"));
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

namespace {

// Cone: 16 (segments) planar side walls around the z axis and the floor z = 0. The
// floor lies through the scale centre, so its plane stays put; floor_expands only says
// whether its material moves radially with the container (and drags what sticks to it).
// Side wall k has its middle at azimuth phi_k = 2 pi k / N, distance r_c from the axis
// at z = 0, and leans outward by theta_c: inward normal
// n_k = (-cos(theta_c) cos(phi_k), -cos(theta_c) sin(phi_k), sin(theta_c)).
void build_cone_walls(ContainerDef& c) {
  const double theta = c.opening_angle_deg * M_PI / 180.0;
  c.walls.clear();
  c.walls.push_back({Vec3::UnitZ(), Vec3::Zero(), WallRole::Bottom, c.floor_expands});
  for (int k = 0; k < c.segments; ++k) {
    const double phi = 2.0 * M_PI * k / c.segments;
    const Vec3 n(-std::cos(theta) * std::cos(phi), -std::cos(theta) * std::sin(phi), std::sin(theta));
    const Vec3 p(c.bottom_radius * std::cos(phi), c.bottom_radius * std::sin(phi), 0.0);
    c.walls.push_back({n, p, WallRole::Side, true});
  }
}

}  // namespace

void read_container(const Reader& r, const json& j, ContainerDef& c) {
  const std::string p = "container";
  if (!j.is_object()) r.fail(p, "an object", &j);
  const std::string type = r.string(j, p, "type", "");
  if (type == "cone") {
    r.object(j, p, {"type", "bottom_radius", "opening_angle_deg", "segments", "height", "floor_expands"});
    c.type = ContainerDef::Type::Cone;
    c.bottom_radius = r.positive(j, p, "bottom_radius", c.bottom_radius);
    c.opening_angle_deg = r.number(j, p, "opening_angle_deg", c.opening_angle_deg, 0.0, 45.0, false,
                                   false, "an angle in degrees in [0, 45]");
    c.segments = static_cast<int>(r.integer(j, p, "segments", c.segments, 3, 1024));
    c.height = r.positive(j, p, "height", c.height);
    c.floor_expands = r.boolean(j, p, "floor_expands", c.floor_expands);
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
      if (w.normal.norm() < kZeroNorm) r.fail(f + ".normal", "a non-zero vector", &planes[i]["normal"]);
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

namespace {

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

}  // namespace

void read_outputs(const Reader& r, const json& j, SceneDef& s) {
  const std::string p = "outputs";
  r.object(j, p, {"timeseries_every", "bodies_every", "volume", "segment_forces", "cycles", "steady_cycles",
                  "displacement", "wall_profile_bins", "settled_profile_time", "vtk_cycles", "vtk_every", "vtk_format",
                  "checkpoint_every", "pressure_window"});
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
  } else if (s.thermal.enabled && s.thermal.cycles > 0) {
    // The default the pressure peaks use (run/pressure_peaks.cpp): the second half.
    r.fill(p, "steady_cycles", json::array({s.thermal.cycles / 2, s.thermal.cycles - 1}));
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
  r.fill(p, "vtk_cycles", json::array());
  o.vtk_every = static_cast<int>(r.integer(j, p, "vtk_every", 0, 0, 1 << 30));
  const std::string format = r.string(j, p, "vtk_format", "binary");
  if (format != "binary" && format != "ascii") r.fail(p + ".vtk_format", "\"binary\" or \"ascii\"", &j.at("vtk_format"));
  o.vtk_ascii = format == "ascii";
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

}  // namespace ratchet::scene_detail

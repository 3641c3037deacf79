#include "ratchet/world/world.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/contact/common_plane.hpp"
#include "ratchet/contact/narrow_phase.hpp"
#include "ratchet/solver/local_coulomb.hpp"

namespace ratchet {

namespace {

// Below this many bodies or pairs a parallel region costs more than it saves.
constexpr int kParallelMin = 256;

// Skew-symmetric cross-product matrix [r]x.
Mat3 skew(const Vec3& r) {
  Mat3 m;
  m << 0.0, -r.z(), r.y(), r.z(), 0.0, -r.x(), -r.y(), r.x(), 0.0;
  return m;
}

// Tangent frame (t1, t2) of a unit normal n, deterministic (Frisvad-free classic choice:
// cross with the axis least aligned with n).
void tangent_frame(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 axis = std::abs(n.x()) < 0.57735 ? Vec3::UnitX() : (std::abs(n.y()) < 0.57735 ? Vec3::UnitY() : Vec3::UnitZ());
  t1 = n.cross(axis).normalized();
  t2 = n.cross(t1);
}

}  // namespace

World::World(const SceneDef& scene) : scene_(scene), settling_(scene.settle.enabled) {
  const std::size_t n = scene_.bodies.size();
  state_.x.resize(n);
  state_.v.resize(n);
  state_.w.resize(n);
  state_.q.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDef& b = scene_.bodies[i];
    state_.x[i] = b.position;
    state_.q[i] = b.orientation;
    state_.v[i] = b.fixed ? Vec3::Zero() : b.velocity;
    state_.w[i] = (b.fixed || !scene_.effects.rotation) ? Vec3::Zero() : b.angular_velocity;
  }
  gravity_on_ = scene_.effects.gravity && scene_.gravity.squaredNorm() > 0.0;
  thermal_on_ = scene_.thermal.enabled && (scene_.effects.particle_expansion || scene_.effects.container_expansion);
  friction_on_ = scene_.effects.friction;
  rotation_on_ = scene_.effects.rotation;
  const ThermalScales s0 = thermal_scales(scene_.thermal, scene_.effects, 0.0);
  state_.T = s0.T;
  state_.s_p = thermal_on_ ? s0.s_p : 1.0;
  state_.s_c = thermal_on_ ? s0.s_c : 1.0;
}

std::vector<PlanItem> World::plan() const {
  const Effects& e = scene_.effects;
  std::vector<PlanItem> p;
  p.push_back({kPhaseNames[0], gravity_on_,
               gravity_on_ ? "effects.gravity is on: v_free = v + h g"
                           : (e.gravity ? "gravity vector is zero" : "effects.gravity is off")});
  p.push_back({kPhaseNames[1], thermal_on_,
               thermal_on_ ? "thermal protocol with " + std::string(e.particle_expansion ? "particle" : "") +
                                 (e.particle_expansion && e.container_expansion ? " and " : "") +
                                 (e.container_expansion ? "container" : "") + " expansion"
                           : (scene_.thermal.enabled ? "effects.particle_expansion and container_expansion are off"
                                                     : "the scene has no thermal protocol")});
  p.push_back({kPhaseNames[2], true, "broad phase (uniform grid) and narrow phase for every pair type present"});
  p.push_back({kPhaseNames[3], true,
               std::string("non-linear Gauss-Seidel, ") +
                   (friction_on_ ? "normal and tangential (Coulomb) parts" : "normal part only: effects.friction is off") +
                   (rotation_on_ ? ", with rotation" : ", no rotation: effects.rotation is off")});
  p.push_back({kPhaseNames[4], true,
               "x += h ((1 - theta) v(t) + theta v(t+h)), q by the exponential map, new scales"});
  p.push_back({kPhaseNames[5], scene_.solver.warm_start,
               scene_.solver.warm_start ? "solver.warm_start is on" : "solver.warm_start is off"});
  p.push_back({kPhaseNames[6], true, "wall forces and active contact count (outputs are written after the step)"});
  return p;
}

// ---------------------------------------------------------------------------------
// The step (design.md section 3). Each phase is timed; skipped phases never run.
void World::step() {
  if (gravity_on_) { PhaseTimer t(timers_, Phase::FreeVelocity); free_velocity(); }
  else { scratch_.v_begin = state_.v; scratch_.w_begin = state_.w; }
  if (thermal_on_) { PhaseTimer t(timers_, Phase::Thermal); thermal(); }
  { PhaseTimer t(timers_, Phase::Detect); detect(); }
  { PhaseTimer t(timers_, Phase::Solve); solve(); }
  { PhaseTimer t(timers_, Phase::Integrate); integrate(); }
  if (scene_.solver.warm_start) { PhaseTimer t(timers_, Phase::KeepImpulses); keep_impulses(); }
  { PhaseTimer t(timers_, Phase::Observe); observe(); }
}

// 1. Free velocities. Gravity acts at the centre of mass: no torque. Mass is constant
// under expansion, so the acceleration is g whatever the scale.
void World::free_velocity() {
  scratch_.v_begin = state_.v;
  scratch_.w_begin = state_.w;
  const double h = scene_.dt;
  for (std::size_t i = 0; i < state_.v.size(); ++i)
    if (!scene_.bodies[i].fixed) state_.v[i] += h * scene_.gravity;
}

// 2. Thermal state at t + h and the expansion rates over the step. The rate
// eps = (s(t+h) - s(t)) / (h s(t)) moves a material point at lever r by exactly the
// change of scale over the step (design.md section 3, item 2).
void World::thermal() {
  const double h = scene_.dt;
  scratch_.next = thermal_scales(scene_.thermal, scene_.effects, state_.t + h);
  scratch_.eps_p = (scratch_.next.s_p - state_.s_p) / (h * state_.s_p);
  scratch_.eps_c = (scratch_.next.s_c - state_.s_c) / (h * state_.s_c);
}

void World::end_settle_stage() {
  if (!settling_) throw std::logic_error(scene_.source + ": end_settle_stage without a settle stage in progress");
  settling_ = false;
  const SettleDef& st = scene_.settle;
  scene_.thermal.start_time = state_.t + st.rest_time;
  scene_.duration = state_.t + st.run_time;
  scene_.steps = state_.step + static_cast<std::int64_t>(std::llround(st.run_time / scene_.dt));
}

Vec3 World::wall_point(int wall) const {
  const WallDef& w = scene_.container.walls[static_cast<std::size_t>(wall)];
  if (!w.expands) return w.point;
  const Vec3& c0 = scene_.container.scale_center;
  return c0 + state_.s_c * (w.point - c0);
}

double World::body_scale(int i) const { return scene_.bodies[static_cast<std::size_t>(i)].fixed ? 1.0 : state_.s_p; }

void World::prepare_bodies() {
  const std::size_t n = scene_.bodies.size();
  StepScratch& s = scratch_;
  s.R.resize(n);
  s.inv_inertia.resize(n);
  s.inv_mass.resize(n);
  s.vertex_offset.resize(n);
  s.centers.resize(n);
  s.radii.resize(n);
  int total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDef& b = scene_.bodies[i];
    s.vertex_offset[i] = b.kind == ShapeKind::Polyhedron ? total : -1;
    if (b.kind == ShapeKind::Polyhedron) total += static_cast<int>(scene_.shapes[static_cast<std::size_t>(b.shape)].vertices.size());
  }
  s.world_vertices.resize(static_cast<std::size_t>(total));
#pragma omp parallel for schedule(static) if (n > static_cast<std::size_t>(kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    const BodyDef& b = scene_.bodies[i];
    const double sc = body_scale(static_cast<int>(i));
    s.R[i] = state_.q[i].toRotationMatrix();
    s.inv_mass[i] = b.fixed ? 0.0 : 1.0 / b.mass;
    if (b.fixed || !rotation_on_) {
      s.inv_inertia[i].setZero();
    } else {
      // Inertia scales with s^2 at constant mass.
      const Vec3 inv_I = (b.principal_inertia * (sc * sc)).cwiseInverse();
      s.inv_inertia[i] = s.R[i] * inv_I.asDiagonal() * s.R[i].transpose();
    }
    s.centers[i] = state_.x[i];
    s.radii[i] = b.bounding_radius * sc;
    if (b.kind == ShapeKind::Polyhedron) {
      const auto& verts = scene_.shapes[static_cast<std::size_t>(b.shape)].vertices;
      Vec3* out = &s.world_vertices[static_cast<std::size_t>(s.vertex_offset[i])];
      for (std::size_t k = 0; k < verts.size(); ++k) out[k] = state_.x[i] + sc * (s.R[i] * verts[k]);
    }
  }
}

// 3. Contact detection: pairs from the grid, then the narrow phase per pair type, in
// parallel into per-pair slots, gathered in pair order (same list for any thread count).
void World::detect() {
  prepare_bodies();
  StepScratch& s = scratch_;
  const double margin = scene_.solver.contact_margin;
  find_candidate_pairs(s.centers, s.radii, margin, s.pairs);
  const int n = static_cast<int>(scene_.bodies.size());
  const int nw = static_cast<int>(scene_.container.walls.size());
  auto view = [&](int i) {
    const BodyDef& b = scene_.bodies[static_cast<std::size_t>(i)];
    PolyhedronView v;
    v.shape = &scene_.shapes[static_cast<std::size_t>(b.shape)];
    v.world_vertices = &s.world_vertices[static_cast<std::size_t>(s.vertex_offset[static_cast<std::size_t>(i)])];
    v.center = state_.x[static_cast<std::size_t>(i)];
    v.R = s.R[static_cast<std::size_t>(i)];
    v.scale = body_scale(i);
    return v;
  };
  auto radius = [&](int i) { return scene_.bodies[static_cast<std::size_t>(i)].radius * body_scale(i); };
  s.pair_manifolds.resize(s.pairs.size());  // every slot's count is set below
  const int np = static_cast<int>(s.pairs.size());
  // Common planes of the last step, looked up by pair (both lists are sorted).
  s.pair_planes.assign(s.pairs.size(), CommonPlaneCache{});
  {
    std::size_t j = 0;
    for (std::size_t k = 0; k < s.pairs.size(); ++k) {
      while (j < state_.planes.size() &&
             std::make_pair(state_.planes[j].a, state_.planes[j].b) < s.pairs[k]) ++j;
      if (j < state_.planes.size() && std::make_pair(state_.planes[j].a, state_.planes[j].b) == s.pairs[k])
        s.pair_planes[k] = state_.planes[j].cache;
    }
  }
#pragma omp parallel for schedule(dynamic, 64) if (np > kParallelMin)
  for (int k = 0; k < np; ++k) {
    const int a = s.pairs[static_cast<std::size_t>(k)].first, b = s.pairs[static_cast<std::size_t>(k)].second;
    ContactManifold& m = s.pair_manifolds[static_cast<std::size_t>(k)];
    m.count = 0;
    const BodyDef& A = scene_.bodies[static_cast<std::size_t>(a)];
    const BodyDef& B = scene_.bodies[static_cast<std::size_t>(b)];
    if (A.fixed && B.fixed) continue;
    if (A.kind == ShapeKind::Sphere && B.kind == ShapeKind::Sphere) {
      collide_sphere_sphere(state_.x[a], radius(a), state_.x[b], radius(b), margin, m);
    } else if (A.kind == ShapeKind::Sphere) {
      collide_sphere_polyhedron(state_.x[a], radius(a), view(b), margin, m);
    } else if (B.kind == ShapeKind::Sphere) {
      // Solve as (sphere, polyhedron), then flip to the pair's A -> B convention.
      collide_sphere_polyhedron(state_.x[b], radius(b), view(a), margin, m);
      for (int c = 0; c < m.count; ++c) {
        ContactPoint& p = m.points[static_cast<std::size_t>(c)];
        p.normal = -p.normal;
        std::swap(p.feature_a, p.feature_b);
      }
    } else {
      collide_polyhedra(view(a), view(b), margin, s.pair_planes[static_cast<std::size_t>(k)], m);
    }
  }
  // Keep the planes of the polyhedron pairs for the next step.
  state_.planes.clear();
  for (int k = 0; k < np; ++k)
    if (s.pair_planes[static_cast<std::size_t>(k)].valid)
      state_.planes.push_back({s.pairs[static_cast<std::size_t>(k)].first, s.pairs[static_cast<std::size_t>(k)].second,
                               s.pair_planes[static_cast<std::size_t>(k)]});
  // Bodies against walls: (body, wall) candidates whose bounding sphere reaches within
  // the margin of the wall plane, body-major, then the narrow phase for those only.
  std::vector<Vec3> wall_points(static_cast<std::size_t>(nw));
  for (int w = 0; w < nw; ++w) wall_points[static_cast<std::size_t>(w)] = wall_point(w);
  s.wall_pairs.clear();
  for (int i = 0; i < n; ++i) {
    if (scene_.bodies[static_cast<std::size_t>(i)].fixed) continue;
    for (int w = 0; w < nw; ++w) {
      const WallDef& wall = scene_.container.walls[static_cast<std::size_t>(w)];
      if (wall.normal.dot(s.centers[static_cast<std::size_t>(i)] - wall_points[static_cast<std::size_t>(w)]) -
              s.radii[static_cast<std::size_t>(i)] <= margin)
        s.wall_pairs.emplace_back(i, w);
    }
  }
  const int nwp = static_cast<int>(s.wall_pairs.size());
  s.wall_manifolds.resize(s.wall_pairs.size());
#pragma omp parallel for schedule(dynamic, 64) if (nwp > kParallelMin)
  for (int k = 0; k < nwp; ++k) {
    const int i = s.wall_pairs[static_cast<std::size_t>(k)].first, w = s.wall_pairs[static_cast<std::size_t>(k)].second;
    const BodyDef& b = scene_.bodies[static_cast<std::size_t>(i)];
    const WallDef& wall = scene_.container.walls[static_cast<std::size_t>(w)];
    ContactManifold& m = s.wall_manifolds[static_cast<std::size_t>(k)];
    const Vec3& p = wall_points[static_cast<std::size_t>(w)];
    if (b.kind == ShapeKind::Sphere) collide_sphere_plane(state_.x[i], radius(i), wall.normal, p, margin, m);
    else collide_polyhedron_plane(view(i), wall.normal, p, margin, m);
  }
  // Gather in a fixed order: body pairs (sorted), then bodies against walls.
  s.contacts.clear();
  for (int k = 0; k < np; ++k) {
    const ContactManifold& m = s.pair_manifolds[static_cast<std::size_t>(k)];
    for (int c = 0; c < m.count; ++c) {
      SolverContact sc;
      sc.a = s.pairs[static_cast<std::size_t>(k)].first;
      sc.b = s.pairs[static_cast<std::size_t>(k)].second;
      sc.geometry = m.points[static_cast<std::size_t>(c)];
      sc.mu = scene_.materials.friction;
      s.contacts.push_back(sc);
    }
  }
  for (int k = 0; k < nwp; ++k) {
    const ContactManifold& m = s.wall_manifolds[static_cast<std::size_t>(k)];
    for (int c = 0; c < m.count; ++c) {
      SolverContact sc;
      sc.a = s.wall_pairs[static_cast<std::size_t>(k)].first;
      sc.b = -1 - s.wall_pairs[static_cast<std::size_t>(k)].second;
      sc.geometry = m.points[static_cast<std::size_t>(c)];
      sc.mu = scene_.materials.wall_friction;
      s.contacts.push_back(sc);
    }
  }
}

// Local relative velocity of A with respect to B at the contact (n, t1, t2), with the
// expansion velocity: u = F^T (v_a - v_b) + J_a w_a - J_b w_b + u0.
inline Vec3 World::local_velocity(const SolverRow& r) const {
  Vec3 dv = state_.v[r.a];
  if (r.b >= 0) dv -= state_.v[r.b];
  Vec3 u = r.F.transpose() * dv + r.u0;
  if (rotation_on_) {
    u += r.Ja * state_.w[r.a];
    if (r.b >= 0) u -= r.Jb * state_.w[r.b];
  }
  return u;
}

// Applies the local impulse change d (on A, minus on B): v += m^-1 F d,
// w += I^-1 J^T d (J^T d = r x (F d), the angular impulse). Forced inline: GCC keeps
// it out of line (two callers), and the call was a tenth of its cost in the sweep.
[[gnu::always_inline]] inline void World::apply_local_impulse(const SolverRow& r, const Vec3& d) {
  const StepScratch& s = scratch_;
  const Vec3 P = r.F * d;
  state_.v[r.a] += s.inv_mass[r.a] * P;
  if (rotation_on_) state_.w[r.a] += s.inv_inertia[r.a] * (r.Ja.transpose() * d);
  if (r.b >= 0) {
    state_.v[r.b] -= s.inv_mass[r.b] * P;
    if (rotation_on_) state_.w[r.b] -= s.inv_inertia[r.b] * (r.Jb.transpose() * d);
  }
}

// Local frames, Delassus blocks W = H^T M^-1 H (Jean 1999, eq. 40), expansion
// velocities and the gap bias of every contact.
void World::build_solver_contacts() {
  StepScratch& s = scratch_;
  const double h = scene_.dt;
  const double p_gap = scene_.solver.p_gap;
  [[maybe_unused]] const Vec3& c0 = scene_.container.scale_center;  // unused in the planted build
  s.rows.resize(s.contacts.size());
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    SolverContact& c = s.contacts[k];
    SolverRow& r = s.rows[k];
    r.a = c.a;
    r.b = c.b;
    r.mu = c.mu;
    const Vec3& n = c.geometry.normal;
    const Vec3& p = c.geometry.point;
    c.ra = p - state_.x[c.a];
    Mat3 K = s.inv_mass[c.a] * Mat3::Identity() - skew(c.ra) * s.inv_inertia[c.a] * skew(c.ra);
    // A material point at lever r from a particle centre moves with eps_p r; a wall
    // point x with eps_c (x - c0) (design.md section 3, item 2).
    // Fixed bodies keep scale 1 (body_scale), so they have no expansion velocity.
    auto eps_of = [&](int body) { return scene_.bodies[static_cast<std::size_t>(body)].fixed ? 0.0 : scratch_.eps_p; };
    c.u_expansion = eps_of(c.a) * c.ra;
    if (c.b >= 0) {
      c.rb = p - state_.x[c.b];
      K += s.inv_mass[c.b] * Mat3::Identity() - skew(c.rb) * s.inv_inertia[c.b] * skew(c.rb);
      c.u_expansion -= eps_of(c.b) * c.rb;
    } else if (scene_.container.walls[static_cast<std::size_t>(-1 - c.b)].expands) {
#ifndef RATCHET_PLANTED_DROP_WALL_EXPANSION  // planted regression (regression/CMakeLists.txt) only
      c.u_expansion -= scratch_.eps_c * (p - c0);
#endif
    }
    // Columns computed one by one with the same expressions in the frictionless and
    // the frictional case, so that mu = 0 reproduces friction-off bit for bit.
    const Vec3 Kn = K * n;
    r.W.setZero();
    r.W(0, 0) = n.dot(Kn);
    if (friction_on_) {
      tangent_frame(n, c.t1, c.t2);
      const Vec3 Kt1 = K * c.t1, Kt2 = K * c.t2;
      r.W(1, 0) = c.t1.dot(Kn); r.W(2, 0) = c.t2.dot(Kn);
      r.W(0, 1) = n.dot(Kt1);   r.W(1, 1) = c.t1.dot(Kt1); r.W(2, 1) = c.t2.dot(Kt1);
      r.W(0, 2) = n.dot(Kt2);   r.W(1, 2) = c.t1.dot(Kt2); r.W(2, 2) = c.t2.dot(Kt2);
    }
    r.F.col(0) = n;
    r.F.col(1) = c.t1;
    r.F.col(2) = c.t2;
    r.Ja.setZero();
    r.Jb.setZero();
    if (rotation_on_) {
      for (int k = 0; k < 3; ++k) {
        r.Ja.row(k) = c.ra.cross(r.F.col(k)).transpose();
        if (c.b >= 0) r.Jb.row(k) = c.rb.cross(r.F.col(k)).transpose();
      }
    }
    r.W_inv.setZero();
    if (friction_on_) r.W_inv = r.W.inverse();
    r.u0 = r.F.transpose() * c.u_expansion;
    // Gap relaxation (design.md s. 2): an overlap closes at p_gap g / h per step.
    const double g = c.geometry.gap;
    const double g_eff = g >= 0.0 ? g : p_gap * g;
    // Velocity-level Signorini (design.md s. 3, item 4): u_n(t+h) >= -g_eff / h. Theta
    // enters the position update only; a gap-based bias with theta < 1 would turn an
    // inelastic landing into a rebound.
    r.bias = g_eff / h;
    r.lambda.setZero();
    c.lambda.setZero();
  }
}

// Impulses of the previous step for the same (bodies, features), projected onto the
// new frame and clipped to the friction cone.
void World::warm_start() {
  if (!scene_.solver.warm_start || state_.impulses.empty()) return;
  StepScratch& s = scratch_;
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const SolverContact& c = s.contacts[k];
    const ContactKey key{c.a, c.b, c.geometry.feature_a, c.geometry.feature_b};
    auto it = std::lower_bound(state_.impulses.begin(), state_.impulses.end(), key,
                               [](const KeptImpulse& x, const ContactKey& y) { return x.key < y; });
    if (it == state_.impulses.end() || !(it->key == key)) continue;
    const Vec3& P = it->impulse;
    const double ln = std::max(0.0, c.geometry.normal.dot(P));
    Vec3 lambda(ln, 0.0, 0.0);
    if (friction_on_) {
      double l1 = c.t1.dot(P), l2 = c.t2.dot(P);
      const double lt = std::hypot(l1, l2), cap = c.mu * ln;
      if (lt > cap) { l1 *= cap / lt; l2 *= cap / lt; }
      if (cap == 0.0) { l1 = 0.0; l2 = 0.0; }
      lambda[1] = l1;
      lambda[2] = l2;
    }
    s.rows[k].lambda = lambda;
    apply_local_impulse(s.rows[k], lambda);
  }
}

// sum_i m_i |v_i - v0_i|^2 + (w_i - w0_i)^T I_i (w_i - w0_i): twice the kinetic energy
// of the velocity difference. Inertia I = R diag(I_p s^2) R^T (as in prepare_bodies).
double World::velocity_change(const std::vector<Vec3>& v0, const std::vector<Vec3>& w0) const {
  double e = 0.0;
  for (std::size_t i = 0; i < state_.v.size(); ++i) {
    const BodyDef& b = scene_.bodies[i];
    if (b.fixed) continue;
    e += b.mass * (state_.v[i] - v0[i]).squaredNorm();
    if (rotation_on_) {
      const double sc = body_scale(static_cast<int>(i));
      const Vec3 dw = scratch_.R[i].transpose() * (state_.w[i] - w0[i]);
      e += (sc * sc) * dw.dot(b.principal_inertia.cwiseProduct(dw));
    }
  }
  return e;
}

// Non-linear Gauss-Seidel (Jean 1999, s. 4; Moreau 1994): sweep the contacts, solve
// each exactly with the others frozen, apply the change at once. Stop when the
// sweep's relative change falls below the tolerance, measured by solver.criterion:
// - impulse: ||d lambda|| / ||lambda||;
// - velocity: sqrt(dE_sweep / E_contact), dE_sweep the kinetic-energy norm of the
//   sweep's change of the body velocities and E_contact that of the change the
//   contact impulses made to the free velocities. It is the norm of H^T d lambda in
//   M^-1 (Jean 1999, eq. 40 for H), so impulses that only move load between redundant
//   contacts of a hyperstatic packing (the null space of H^T) do not count: they
//   change no velocity. Close to LMGC90's 'Quad' norm, which divides the change of
//   the local velocities by W lambda.
void World::gauss_seidel() {
  std::vector<SolverRow>& cs = scratch_.rows;
  StepScratch& s = scratch_;
  const double tol = scene_.solver.tolerance;
  const bool by_velocity = scene_.solver.criterion == Criterion::Velocity;
  int it = 0;
  double residual = 0.0;
  const int half = scene_.solver.max_iterations / 2;
  double normal_half = -1.0;  // sum of the normal impulses after half the allowed sweeps
  std::int64_t tangential = 0;
  for (it = 1; it <= scene_.solver.max_iterations && !cs.empty(); ++it) {
    if (by_velocity) { s.v_sweep = state_.v; s.w_sweep = state_.w; }
    double d2 = 0.0, l2 = 0.0;
    for (SolverRow& c : cs) {
      const Vec3 u = local_velocity(c);
      Vec3 lambda_new;
      if (friction_on_) {
        // w = u - W lambda (velocity without this contact's impulse) + bias on the normal.
        Vec3 w = u - c.W * c.lambda;
        w[0] += c.bias;
        lambda_new = solve_local_coulomb(c.W, c.W_inv, w, c.mu).lambda;
        ++tangential;
      } else {
        const double w_n = u[0] - c.W(0, 0) * c.lambda[0] + c.bias;
        lambda_new = Vec3(solve_local_normal(c.W(0, 0), w_n), 0.0, 0.0);
      }
      const Vec3 d = lambda_new - c.lambda;
      if (d.squaredNorm() > 0.0) apply_local_impulse(c, d);
      c.lambda = lambda_new;
      d2 += d.squaredNorm();
      l2 += lambda_new.squaredNorm();
    }
    if (by_velocity) {
      const double de = velocity_change(s.v_sweep, s.w_sweep), e = velocity_change(s.v_free, s.w_free);
      residual = e > 0.0 ? std::sqrt(de / e) : std::sqrt(de);
    } else {
      residual = l2 > 0.0 ? std::sqrt(d2 / l2) : std::sqrt(d2);
    }
    if (it == half) {
      normal_half = 0.0;
      for (const SolverRow& c : cs) normal_half += c.lambda[0];
    }
    if (residual < tol) break;
  }
  stats_.iterations = cs.empty() ? 0 : std::min(it, scene_.solver.max_iterations);
  stats_.converged = cs.empty() || residual < tol;
  double normal_end = 0.0;
  for (const SolverRow& c : cs) normal_end += c.lambda[0];
  // An unconverged step whose normal impulses still grew by half over the second half
  // of its sweeps signals a rigid problem with no solution: there they grow in
  // proportion to the sweep count (see keep_impulses). A solvable problem that is
  // merely slow has settled its normal impulses long before.
  stats_.normal_growth = !stats_.converged && normal_half >= 0.0 && normal_end > 1.5 * normal_half;
  if (!stats_.converged) ++stats_.unconverged_steps;
  stats_.residual = residual;
  stats_.tangential_solves += tangential;
  stats_.total_iterations += stats_.iterations;
}

// 4. Solve.
void World::solve() {
  build_solver_contacts();
  if (scene_.solver.criterion == Criterion::Velocity) { scratch_.v_free = state_.v; scratch_.w_free = state_.w; }
  warm_start();
  gauss_seidel();
  for (std::size_t k = 0; k < scratch_.contacts.size(); ++k) scratch_.contacts[k].lambda = scratch_.rows[k].lambda;
}

// 5. Positions: x += h ((1 - theta) v(t) + theta v(t+h)); orientation by the exponential
// map of h omega; the new scales.
void World::integrate() {
  const double h = scene_.dt;
  const double theta = scene_.solver.theta;
  StepScratch& s = scratch_;
  for (std::size_t i = 0; i < state_.x.size(); ++i) {
    if (scene_.bodies[i].fixed) continue;
    const Vec3 v = theta == 1.0 ? state_.v[i] : Vec3((1.0 - theta) * s.v_begin[i] + theta * state_.v[i]);
    state_.x[i] += h * v;
    if (rotation_on_) {
      const Vec3 w = theta == 1.0 ? state_.w[i] : Vec3((1.0 - theta) * s.w_begin[i] + theta * state_.w[i]);
      const double angle = h * w.norm();
      if (angle > 0.0) {
        state_.q[i] = (Quat(Eigen::AngleAxisd(angle, w / w.norm())) * state_.q[i]).normalized();
      }
    }
  }
  state_.t += h;
  ++state_.step;
  if (thermal_on_) {
    state_.T = scratch_.next.T;
    state_.s_p = scratch_.next.s_p;
    state_.s_c = scratch_.next.s_c;
  } else if (scene_.thermal.enabled) {
    state_.T = temperature(scene_.thermal, state_.t);
  }
}

// 6. Keep the impulses keyed by (bodies, features), sorted for binary search.
// Warm starting continues the sweeps of the last step, which is what lets frictional
// contacts that must build up stress over many sweeps (an expanding particle stuck on
// three points) converge over a few steps. But when the rigid problem has no solution
// (a body jammed between walls it outgrows) the normal impulses grow with every sweep;
// carrying those on would make the forces grow without bound from step to step, so an
// unconverged step whose normal impulses were still growing in proportion to the sweep
// count is not kept
// (validation/single_particle_test.cpp, jammed sphere).
void World::keep_impulses() {
  state_.impulses.clear();
  if (stats_.normal_growth) return;
  for (const SolverContact& c : scratch_.contacts) {
    if (c.lambda[0] <= 0.0) continue;
    state_.impulses.push_back({{c.a, c.b, c.geometry.feature_a, c.geometry.feature_b},
                               c.geometry.normal * c.lambda[0] + c.t1 * c.lambda[1] + c.t2 * c.lambda[2]});
  }
  std::sort(state_.impulses.begin(), state_.impulses.end(),
            [](const KeptImpulse& x, const KeptImpulse& y) { return x.key < y.key; });
}

// 7. Observers: wall forces from the wall impulses (F = lambda_n / h).
void World::observe() {
  double side = 0.0, bottom = 0.0, total = 0.0;
  int active = 0;
  for (const SolverContact& c : scratch_.contacts) {
    if (c.lambda[0] > 0.0) ++active;
    if (c.b >= 0) continue;
    total += c.lambda[0];
    const WallRole role = scene_.container.walls[static_cast<std::size_t>(-1 - c.b)].role;
    if (role == WallRole::Side) side += c.lambda[0];
    else if (role == WallRole::Bottom) bottom += c.lambda[0];
  }
  stats_.contacts = active;
  stats_.wall_force_side = side / scene_.dt;
  stats_.wall_force_bottom = bottom / scene_.dt;
  stats_.wall_force_total = total / scene_.dt;
}

double World::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < state_.v.size(); ++i) {
    const BodyDef& b = scene_.bodies[i];
    if (b.fixed) continue;
    e += 0.5 * b.mass * state_.v[i].squaredNorm();
    if (rotation_on_) {
      const double sc = state_.s_p;
      const Vec3 w_body = state_.q[i].conjugate() * state_.w[i];
      e += 0.5 * w_body.dot((b.principal_inertia * (sc * sc)).cwiseProduct(w_body));
    }
  }
  return e;
}

double World::bed_height() const {
  double top = 0.0;
  for (std::size_t i = 0; i < state_.x.size(); ++i) {
    const BodyDef& b = scene_.bodies[i];
    if (b.fixed) continue;
    const double sc = body_scale(static_cast<int>(i));
    if (b.kind == ShapeKind::Sphere) {
      top = std::max(top, state_.x[i].z() + b.radius * sc);
    } else {
      const Mat3 R = state_.q[i].toRotationMatrix();
      for (const Vec3& v : scene_.shapes[static_cast<std::size_t>(b.shape)].vertices)
        top = std::max(top, state_.x[i].z() + sc * R.row(2).dot(v));
    }
  }
  return top;
}

// Lateral area of the 16-sided frustum from z = 0 to `height`: each face is a trapezoid
// of widths 2 a(z) tan(pi/N) with apothem a(z) = s_c r_c + z tan(theta_c), slant
// height H / cos(theta_c).
double World::wetted_side_area(double height) const {
  const ContainerDef& c = scene_.container;
  if (c.type != ContainerDef::Type::Cone || height <= 0.0) return 0.0;
  const double th = c.opening_angle_deg * M_PI / 180.0;
  const double a0 = state_.s_c * c.bottom_radius, a1 = a0 + height * std::tan(th);
  const double half = std::tan(M_PI / c.segments);
  return c.segments * (a0 + a1) * half * height / std::cos(th);
}

double World::pressure() const {
  const double area = wetted_side_area(bed_height());
  return area > 0.0 ? stats_.wall_force_side / area : 0.0;
}

}  // namespace ratchet

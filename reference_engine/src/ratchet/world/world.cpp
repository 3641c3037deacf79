#include "ratchet/world/world.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ratchet/solver/nsgs.hpp"
#include "ratchet/world/test_hooks.hpp"
#include "ratchet/world/thread_share.hpp"

namespace ratchet {


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
    body_mass_.push_back(b.fixed ? 0.0 : b.mass);
    body_inertia_.push_back(b.principal_inertia);
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
               std::string(scene_.solver.acceleration == Acceleration::Anderson
                               ? "non-linear Gauss-Seidel with Anderson acceleration (depth " +
                                     std::to_string(scene_.solver.anderson_depth) + "), "
                               : "non-linear Gauss-Seidel, ") +
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
// The step (docs/method.md). Each phase is timed; skipped phases never run.
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
// change of scale over the step (docs/method.md s. 2).
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

WorldProgress World::progress() const {
  WorldProgress p;
  p.settling = settling_;
  p.start_time = scene_.thermal.start_time;
  p.duration = scene_.duration;
  p.steps = scene_.steps;
  p.totals = totals_;
  p.timers = timers_;
  return p;
}

void World::restore_progress(const WorldProgress& p) {
  if (p.settling && !settling_)
    throw std::logic_error(scene_.source + ": restore_progress: a settle stage that this scene does not have");
  settling_ = p.settling;
  scene_.thermal.start_time = p.start_time;
  scene_.duration = p.duration;
  scene_.steps = p.steps;
  totals_ = p.totals;
  timers_ = p.timers;
}

Vec3 World::wall_point(int wall) const {
  const WallDef& w = scene_.container.walls[static_cast<std::size_t>(wall)];
  if (!w.expands) return w.point;
  const Vec3& c0 = scene_.container.scale_center;
  return c0 + state_.s_c * (w.point - c0);
}

double World::body_scale(int i) const {
  return ratchet::body_scale(scene_.bodies[static_cast<std::size_t>(i)], state_.s_p);
}

// 4. Solve: the rows of this step's contacts, their warm start, the global solve
// (solver/nsgs.hpp).
void World::solve() {
  build_rows();
  SolverBodies bodies{state_.v, state_.w, scratch_.inv_mass, scratch_.inv_inertia, scratch_.R,
                      body_mass_, body_inertia_, scratch_.scale};
  SolveSettings settings;
  settings.tolerance = scene_.solver.tolerance;
  settings.max_iterations = scene_.solver.max_iterations;
  settings.by_velocity = scene_.solver.criterion == Criterion::Velocity;
  settings.friction = friction_on_;
  settings.rotation = rotation_on_;
  if (scene_.solver.acceleration == Acceleration::Anderson) settings.anderson_depth = scene_.solver.anderson_depth;
  settings.compliance = scene_.solver.compliance;
  settings.rigid = scene_.solver.compliance == 0.0;
  settings.apgd_fallback = scene_.solver.stall_fallback == StallFallback::Apgd;
  settings.slide_newton_steps = scene_.solver.slide_newton_steps;
  settings.colouring = &scratch_.colouring;
  settings.parallel_min_rows = parallel_min_rows();
  scratch_.solver.v_free = state_.v;  // stored once: the velocity criterion and the jam's re-solve read it
  scratch_.solver.w_free = state_.w;
  warm_start(bodies);
  SolveResult r = solve_contacts(bodies, settings);
  int sweeps = r.sweeps;
  std::int64_t tangential = r.tangential_solves;
  const bool jammed = settings.rigid && (r.normal_growth || r.persistent_growth);
  const double first_residual = r.residual;
  if (jammed) {
    yield_to_jam(bodies);
    r = solve_contacts(bodies, settings);
    sweeps += r.sweeps;
    tangential += r.tangential_solves;
    ++totals_.jammed_steps;
  }
  stats_.iterations = sweeps;
  stats_.converged = r.converged && !jammed;
  stats_.normal_growth = jammed || r.normal_growth;
  stats_.residual = jammed ? first_residual : r.residual;  // the problem posed, not the one yielded
  if (!stats_.converged) ++totals_.unconverged_steps;
  if (r.relaxation < 1.0) ++totals_.relaxed_steps;
  totals_.tangential_solves += tangential;
  totals_.total_iterations += sweeps;
  const int n = static_cast<int>(scratch_.contacts.size());
#pragma omp parallel for schedule(static) if (n > parallel_min_rows())
  for (int k = 0; k < n; ++k)
    scratch_.contacts[static_cast<std::size_t>(k)].lambda = scratch_.rows[static_cast<std::size_t>(k)].lambda;
}

// 4a. The global solve of the step's rows by solver.method: the one place a method is chosen.
SolveResult World::solve_contacts(SolverBodies& bodies, const SolveSettings& settings) {
  switch (scene_.solver.method) {
    case SolverMethod::Nsgs: return solve_nsgs(scratch_.rows, bodies, settings, scratch_.solver);
  }
  throw std::logic_error(scene_.source + ": solver.method without a solve");  // unreachable: the reader refuses it
}

// 4b. A rigid problem with no solution (the normal impulses still grew at the cap): bodies
// that outgrow the room they have, a jam. Rigid bodies cannot make room, and pushing
// with impulses set by the cap would give the bed energy from nowhere, so the step is
// solved again, from the free velocities and cold, with what the step imposes taken
// out: the expansion velocities and the separation an overlap asks for. That problem
// always has a solution (the bodies at rest satisfy it), the contacts only take energy,
// and the overlap of the jam grows by the imposed expansion until the geometry frees it
// (docs/method.md, "Infeasible jam"). Compliant contacts always have a solution and never
// come here.
void World::yield_to_jam(SolverBodies& bodies) {
  bodies.v = scratch_.solver.v_free;
  bodies.w = scratch_.solver.w_free;
  for (SolverRow& r : scratch_.rows) {
    r.u0.setZero();
    r.bias = std::max(r.bias, 0.0);
    r.bias_capped = 0.0;
    r.lambda.setZero();
  }
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
  // The loaded contacts in their order, each thread writing its share's at the place a
  // count of the shares before it gives: the list one thread would make.
  const std::vector<SolverContact>& contacts = scratch_.contacts;
  const int n = static_cast<int>(contacts.size());
  std::vector<int> share_begin;
#pragma omp parallel if (n > parallel_min_rows())
  {
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
    const auto [begin, end] = thread_share(n);
#pragma omp single
    share_begin.assign(static_cast<std::size_t>(threads) + 1, 0);
    int loaded = 0;
    for (int k = begin; k < end; ++k) loaded += contacts[static_cast<std::size_t>(k)].lambda[0] > 0.0;
    share_begin[static_cast<std::size_t>(me) + 1] = loaded;
#pragma omp barrier
#pragma omp single
    {
      for (int t = 0; t < threads; ++t) share_begin[static_cast<std::size_t>(t) + 1] += share_begin[static_cast<std::size_t>(t)];
      state_.impulses.resize(static_cast<std::size_t>(share_begin.back()));
    }
    std::size_t at = static_cast<std::size_t>(share_begin[static_cast<std::size_t>(me)]);
    for (int k = begin; k < end; ++k) {
      const SolverContact& c = contacts[static_cast<std::size_t>(k)];
      if (c.lambda[0] <= 0.0) continue;
      state_.impulses[at++] = {{c.a, c.b, c.geometry.feature_a, c.geometry.feature_b},
                               c.geometry.normal * c.lambda[0] + c.t1 * c.lambda[1] + c.t2 * c.lambda[2]};
    }
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
    if (!is_wall(c.b)) continue;
    total += c.lambda[0];
    const WallRole role = scene_.container.walls[static_cast<std::size_t>(wall_index(c.b))].role;
    if (role == WallRole::Side) side += c.lambda[0];
    else if (role == WallRole::Bottom) bottom += c.lambda[0];
  }
  stats_.contacts = active;
  stats_.wall_force_side = side / scene_.dt;
  stats_.wall_force_bottom = bottom / scene_.dt;
  stats_.wall_force_total = total / scene_.dt;
}

}  // namespace ratchet

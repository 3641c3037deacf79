#include "support/hard_case.hpp"

#include <algorithm>
#include <cstdio>

#include "ratchet/observe/energy.hpp"
#include "ratchet/run/runner.hpp"
#include "support/check_record.hpp"

namespace ratchet::hard_case {

Outcome run_scene(const nlohmann::json& j, const std::function<void(const SceneDef&)>& inspect,
                  const std::function<void(const World&)>& watch) {
  World world(build_scene(j, j.at("name").get<std::string>() + ".json"));
  if (inspect) inspect(world.scene());
  Outcome o;
  const SceneDef& s = world.scene();
  const double g = s.gravity.norm();
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    if (s.bodies[i].fixed) continue;
    o.e0 += s.bodies[i].mass * g * world.state().x[i].z();
    o.r_min = std::min(o.r_min, s.bodies[i].bounding_radius);
    o.mass += s.bodies[i].mass;
  }
  o.e0 += kinetic_energy(s, world.state());  // zero unless a case starts bodies moving
  try {
    const RunResult r = run_world(world, {}, [&](const World& w) {
      const double ke = kinetic_energy(w.scene(), w.state());
      o.ke_max = std::max(o.ke_max, ke);
      o.ke_end = ke;
      double pe = 0.0;
      for (std::size_t i = 0; i < w.scene().bodies.size(); ++i)
        if (!w.scene().bodies[i].fixed) pe += w.scene().bodies[i].mass * g * w.state().x[i].z();
      o.e_excess = std::max(o.e_excess, ke + pe - o.e0);
      o.overlap_max = std::max(o.overlap_max, w.stats().max_overlap);
      o.overlap_end = w.stats().max_overlap;
      o.side_force_max = std::max(o.side_force_max, w.stats().wall_force_side);
      if (!w.stats().converged) ++o.capped_seen;
      if (w.stats().contacts > 0) ++o.steps_with_contacts;
      if (watch) watch(w);
    });
    o.warnings = r.warnings;
  } catch (const RunError& e) {
    o.failed = true;
    o.error = e.what();
  }
  o.steps = world.state().step;
  o.unconverged = world.totals().unconverged_steps;
  o.jammed = world.totals().jammed_steps;
  std::printf("[%s] excess %.4g  mass %.4g  steps %lld  KE max %.6g  E0 %.6g  KE end %.3g  overlap max %.4g  r_min %.3g  capped %lld of %lld "
              "with contacts  %s\n",
              s.name.c_str(), o.e_excess, o.mass, static_cast<long long>(o.steps), o.ke_max, o.e0, o.ke_end, o.overlap_max, o.r_min,
              static_cast<long long>(o.unconverged), static_cast<long long>(o.steps_with_contacts),
              o.failed ? o.error.c_str() : o.warnings.dump().c_str());
  return o;
}

bool warned(const Outcome& o, const std::string& text) {
  for (const auto& w : o.warnings)
    if (w.get<std::string>().find(text) != std::string::npos) return true;
  return false;
}

bool check_completed(const std::string& name, const Outcome& o) {
  return validation::record(name, "run completed without RunError", o.failed ? 1.0 : 0.0, "0", "exact", !o.failed,
                            o.failed ? "failed: " + o.error
                                     : "no NaN, no centre behind a wall by more than its size, no overlap deeper "
                                       "than the smallest body (run/state_bounds.cpp)");
}

// The mechanical energy E(t) = KE + sum m g z never rises above E0 by more than one
// capped relaxation per body: Moreau-Jean with theta = 1 loses g^2 h^2 / 2 per step of
// free flight, inelastic contacts and friction only take energy, and the relaxation
// gives at most m g max(delta, margin) per correction (docs/method.md s. 5). Tighter than
// max KE <= E0 (which the free fall before the first landing decides): this one watches
// every contact step.
bool check_energy_gain(const std::string& name, const Outcome& o) {
  return validation::check_le(name, "max(KE + sum m g z) - E0", o.e_excess, o.mass * 1.0 * 0.05,
                              "mechanical energy: theta = 1 and the inelastic, frictional contacts only take it; "
                              "the capped relaxation may give m g margin per body: sum m g 0.05 = " +
                                  validation::format_number(o.mass * 0.05));
}

nlohmann::json pour_scene(const std::string& name, int count) {
  return {{"name", name},
          {"seed", 3},
          {"time", {{"dt", 0.004}, {"duration", 7.0}}},
          {"container", {{"type", "cone"}, {"bottom_radius", 5.0}, {"segments", 8}, {"opening_angle_deg", 2.0}}},
          {"particles", {{"generate", {{"count", count}, {"vertices", 12}}}}},
          {"outputs", {{"volume", false}}}};
}


}  // namespace ratchet::hard_case

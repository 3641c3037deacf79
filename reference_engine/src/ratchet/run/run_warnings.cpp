#include "ratchet/run/run_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ratchet/geometry/particle_generator.hpp"
#include "ratchet/io/json_numbers.hpp"

namespace ratchet {

double largest_body_travel(const World& world) {
  double v2 = 0.0;
  const auto& bodies = world.scene().bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (!bodies[i].fixed) v2 = std::max(v2, world.state().v[i].squaredNorm());
  return std::sqrt(v2) * world.scene().dt;
}

double largest_wall_travel(const World& world, double s_c_before) {
  const ContainerDef& c = world.scene().container;
  const double ds = std::abs(world.state().s_c - s_c_before);
  double travel = 0.0;
  for (const WallDef& w : c.walls)
    if (w.expands) travel = std::max(travel, ds * std::abs(w.normal.dot(w.point - c.scale_center)));
  return travel;
}

std::string squeeze_warning(const SceneDef& scene) {
  const ThermalProtocol& p = scene.thermal;
  if (!p.enabled || p.cycles == 0 || scene.container.type != ContainerDef::Type::Cone) return {};
  const Effects& e = scene.effects;
  const double s_p = e.particle_expansion ? 1.0 + p.alpha_p * (p.T1 - p.T0) : 1.0;
  const double s_c = e.container_expansion
                         ? 1.0 + p.alpha_c * (p.T1 - p.T0) : 1.0;
  const double room = s_c / s_p;
  if (!(room < 1.0)) return {};
  char text[400];
  std::snprintf(text, sizeof text,
                "at T1 the container scale over the particle scale is %.4g (s_c = %.4g, s_p = %.4g): the bed has %.3g %% "
                "less room than it was poured in, so it must rise out of the container or jam; the thermal.alpha_c "
                "and thermal.alpha_p of the paper give a ratio of at least 1",
                room, s_c, s_p, 100.0 * (1.0 - room));
  return text;
}

RunWarnings::RunWarnings(const nlohmann::json& saved)
    : first_capped_(saved.at("first_capped").get<std::int64_t>()),
      first_capped_t_(number_from_json(saved.at("first_capped_t"))),
      first_capped_residual_(number_from_json(saved.at("first_capped_residual"))),
      first_fast_(saved.at("first_fast").get<std::int64_t>()),
      fast_steps_(saved.at("fast_steps").get<std::int64_t>()),
      fastest_travel_(number_from_json(saved.at("fastest_travel"))),
      first_fast_wall_(saved.at("first_fast_wall").get<std::int64_t>()),
      fast_wall_steps_(saved.at("fast_wall_steps").get<std::int64_t>()),
      fastest_wall_travel_(number_from_json(saved.at("fastest_wall_travel"))) {}

nlohmann::json RunWarnings::save() const {
  return {{"first_capped", first_capped_},
          {"first_capped_t", json_number(first_capped_t_)},
          {"first_capped_residual", json_number(first_capped_residual_)},
          {"first_fast", first_fast_},
          {"fast_steps", fast_steps_},
          {"fastest_travel", json_number(fastest_travel_)},
          {"first_fast_wall", first_fast_wall_},
          {"fast_wall_steps", fast_wall_steps_},
          {"fastest_wall_travel", json_number(fastest_wall_travel_)}};
}

bool RunWarnings::after_step(const World& world, double s_c_before) {
  const std::int64_t k = world.state().step;
  const double margin = world.scene().solver.contact_margin;
  const double travel = largest_body_travel(world);
  if (travel > margin) {
    if (first_fast_ < 0) first_fast_ = k;
    ++fast_steps_;
    fastest_travel_ = std::max(fastest_travel_, travel);
  }
  const double wall_travel = largest_wall_travel(world, s_c_before);
  if (wall_travel > margin) {
    if (first_fast_wall_ < 0) first_fast_wall_ = k;
    ++fast_wall_steps_;
    fastest_wall_travel_ = std::max(fastest_wall_travel_, wall_travel);
  }
  if (world.stats().converged || first_capped_ >= 0) return false;
  first_capped_ = k;
  first_capped_t_ = world.state().t;
  first_capped_residual_ = world.stats().residual;
  return true;
}

nlohmann::json RunWarnings::sentences(const World& world) const {
  const SceneDef& scene = world.scene();
  const long long steps = static_cast<long long>(world.state().step);
  nlohmann::json out = nlohmann::json::array();
  char text[640];
  if (const std::string squeeze = squeeze_warning(scene); !squeeze.empty()) out.push_back(squeeze);
  if (first_capped_ >= 0) {
    std::snprintf(text, sizeof text,
                  "%lld of %lld steps stopped at solver.max_iterations = %d sweeps unconverged, the first at step %lld "
                  "(t = %.6g, residual %.3g against the tolerance %.3g)",
                  static_cast<long long>(world.totals().unconverged_steps), steps, scene.solver.max_iterations,
                  static_cast<long long>(first_capped_), first_capped_t_, first_capped_residual_, scene.solver.tolerance);
    out.push_back(text);
  }
  if (world.totals().jammed_steps > 0) {
    std::snprintf(text, sizeof text,
                  "%lld of these steps were jams (the rigid contact problem had no solution: the normal impulses "
                  "still grew at the cap) and were solved again without the imposed expansion and gap relaxation, "
                  "so the bodies kept the overlap the expansion made (docs/method.md, \"Infeasible jam\"); "
                  "solver.compliance > 0 gives such contacts a finite stiffness instead",
                  static_cast<long long>(world.totals().jammed_steps));
    out.push_back(text);
  }
  if (scene.redrawn_particles > 0)
    out.push_back(std::to_string(scene.redrawn_particles) + " generated particle(s) were slivers (inradius below " +
                  std::to_string(kMinInradius) +
                  " of their radius) and were drawn again: particles.generate.vertices is low");
  // Bodies and walls that outrun the margin: the same sentence, what moved and the cure.
  auto travel = [&](const char* what, std::int64_t count, double largest, std::int64_t first, const char* cure) {
    std::snprintf(text, sizeof text,
                  "in %lld of %lld steps %s farther than solver.contact_margin = %.3g per step (at most %.3g, the "
                  "first at step %lld): %s",
                  static_cast<long long>(count), steps, what, scene.solver.contact_margin, largest,
                  static_cast<long long>(first), cure);
    out.push_back(text);
  };
  if (first_fast_ >= 0)
    travel("a body moved", fast_steps_, fastest_travel_, first_fast_,
           "contacts may be found only after they overlap; a smaller time.dt or a larger margin avoids it");
  if (first_fast_wall_ >= 0)
    travel("a container wall moved along its normal", fast_wall_steps_, fastest_wall_travel_, first_fast_wall_,
           "the thermal protocol changes the container scale faster than contacts can follow; longer "
           "heat_time/cool_time or a smaller time.dt avoids it");
  return out;
}

}  // namespace ratchet

#include "ratchet/observe/energy.hpp"

namespace ratchet {

// The arithmetic (and its order) of the former World::kinetic_energy: the timeseries
// column must not change by a bit (docs/output-format.md, "Number formatting").
double kinetic_energy(const SceneDef& scene, const State& state) {
  const bool rotation = scene.effects.rotation;
  double e = 0.0;
  for (std::size_t i = 0; i < state.v.size(); ++i) {
    const BodyDef& b = scene.bodies[i];
    if (b.fixed) continue;
    e += 0.5 * b.mass * state.v[i].squaredNorm();
    if (rotation) {
      const double sc = state.s_p;
      const Vec3 w_body = state.q[i].conjugate() * state.w[i];
      e += 0.5 * w_body.dot((b.principal_inertia * (sc * sc)).cwiseProduct(w_body));
    }
  }
  return e;
}

}  // namespace ratchet

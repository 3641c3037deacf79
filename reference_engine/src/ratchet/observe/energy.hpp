// Kinetic energy of the bed (docs/method.md s. 10, "Kinetic energy"): the
// `kinetic_energy` column of timeseries.csv and the settle criterion (run/packing.hpp).
#pragma once

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

// Sum over the non-fixed bodies of 1/2 m |v|^2, plus 1/2 w_b^T diag(s_p^2 I) w_b
// (w_b = q^-1 w, body frame) when scene.effects.rotation is on.
double kinetic_energy(const SceneDef& scene, const State& state);

}  // namespace ratchet

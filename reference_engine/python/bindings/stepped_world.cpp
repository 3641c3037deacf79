#include "stepped_world.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "ratchet/observe/energy.hpp"

namespace ratchet_python {
namespace {

// As the program does before building its world; results do not depend on it.
const ratchet::SceneDef& with_threads(const ratchet::SceneDef& scene) {
#ifdef _OPENMP
  if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
#endif
  return scene;
}

}  // namespace

SteppedWorld::SteppedWorld(const ratchet::SceneDef& scene) : world_(with_threads(scene)) { settle_.emplace(world_); }

void SteppedWorld::step(std::int64_t n) {
  for (std::int64_t i = 0; i < n; ++i) {
    world_.step();
    if (!std::isfinite(ratchet::kinetic_energy(world_.scene(), world_.state())))
      throw std::runtime_error(world_.scene().source + ": the state became non-finite at step " +
                               std::to_string(world_.state().step) + "; the time step may be too large");
    settle_->after_step(world_);
  }
}

}  // namespace ratchet_python

// A World stepped as `ratchet run` steps it (run/runner.cpp): after each step the
// settle monitor may end the settle stage, and a non-finite state stops with an error.
// Without the monitor a scene with a settle section would never start its cycling.
#pragma once

#include <cstdint>
#include <optional>

#include "ratchet/run/packing.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet_python {

class SteppedWorld {
 public:
  explicit SteppedWorld(const ratchet::SceneDef& scene);
  // n steps; throws std::runtime_error naming the step when the state turns non-finite.
  void step(std::int64_t n);
  const ratchet::World& world() const { return world_; }

 private:
  ratchet::World world_;
  std::optional<ratchet::SettleMonitor> settle_;
};

}  // namespace ratchet_python

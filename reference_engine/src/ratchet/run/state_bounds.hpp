// Whether a run's state is still physical (docs/output-format.md, "When a run fails"):
// no free body's centre beyond a wall of the (convex) container by more than its size,
// no overlap deeper than the smallest body's bounding radius, no body that moved more than
// its bounding radius in the last step (speed x time.dt). A state outside these is
// not a slow convergence but a failed step; the runner stops there with this text.
#pragma once

#include <string>

#include "ratchet/world/world.hpp"

namespace ratchet {

// Empty when the state is within the bounds; else what is wrong, naming the bodies
// (at most a few) and the wall or overlap.
std::string unphysical_state(const World& world);

}  // namespace ratchet

// The contacts of the last step as a dict of numpy arrays. A copy: the engine's contact
// list is an array of structs rebuilt (and possibly moved) by every step.
#pragma once

#include <pybind11/pybind11.h>

#include "ratchet/world/world.hpp"

namespace ratchet_python {

// Keys: a, b (b < 0: wall -1 - b), point, normal, gap, mu, impulse (local n, t1, t2,
// on A), force (world frame, on A: the impulse over h). docs/python.md lists them.
pybind11::dict contact_arrays(const ratchet::World& world);

}  // namespace ratchet_python

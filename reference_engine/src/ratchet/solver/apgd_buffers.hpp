// The arrays of the gradient fallback (solver/apgd.hpp), kept in the solve's scratch like
// Anderson's: nothing in them is read before the solve that uses them has written it.
#pragma once

#include <vector>

#include "ratchet/core/types.hpp"

namespace ratchet {

struct ApgdBuffers {
  std::vector<double> s;            // per row: de Saxcé's shift mu |u_t| of the current convex problem
  std::vector<Vec3> x, y, prev, next;  // per row: the iterate, the extrapolated point, the last and the next iterate
  std::vector<Vec3> g;              // per row: the gradient at y
  std::vector<Vec3> vy, wy, vp, wp, vn, wn;  // per body: the velocities of y, of the last and of the next iterate
};

}  // namespace ratchet

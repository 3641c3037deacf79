// The arrays of Anderson's acceleration (solver/anderson.hpp), kept in the solve's
// scratch from step to step: a bed of 2000 has about 27,000 unknowns, and arrays made
// anew at each solve cost a zero fill of fresh pages, about 4 MB per step
// (docs/performance.md). Nothing in them is read before the solve that uses them has
// written it (AndersonMixer).
#pragma once

#include <vector>

namespace ratchet {

struct AndersonBuffers {
  std::vector<double> x, f_prev, g_prev, f, g;  // 3 per row: a sweep's start, residual, result
  std::vector<double> vel, vel_prev;            // 6 per body: the velocities after a sweep
  std::vector<std::vector<double>> dF, dG, dV;  // the ring of difference columns
  std::vector<double> weight;                   // sqrt(W_nn) per row
  std::vector<double> partial;                  // per block of rows: the sums of a pass
  std::vector<double> raw;                      // the unprojected extrapolation (3 per row)
  std::vector<double> vel_mix;                  // 6 per body: the extrapolated velocities
};

}  // namespace ratchet

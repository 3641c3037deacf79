// Homogeneous temperature T(t) of the paper's thermal cycle (Iliev et al., Fig. 1c):
// linear heating T0 -> T1, hold, linear cooling T1 -> T0, hold; repeated `cycles`
// times, then T0. Scales: s_p = 1 + alpha_p (T - T0) for particles (paper eq. 2),
// s_c = 1 + alpha_c (T - T0) for the container (docs/method.md s. 2).
#pragma once

#include "ratchet/scene/scene.hpp"

namespace ratchet {

double temperature(const ThermalProtocol& p, double t);

// Index of the cycle that time t belongs to (0-based; `cycles` once the protocol ended).
int cycle_index(const ThermalProtocol& p, double t);

struct ThermalScales {
  double T = 0.0;
  double s_p = 1.0;  // particle scale
  double s_c = 1.0;  // container scale
};

// Scales at time t; an effect the scene does not call for keeps its scale at 1.
ThermalScales thermal_scales(const ThermalProtocol& p, const Effects& e, double t);

}  // namespace ratchet

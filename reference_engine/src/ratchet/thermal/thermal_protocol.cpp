#include "ratchet/thermal/thermal_protocol.hpp"

#include <cmath>

namespace ratchet {

double temperature(const ThermalProtocol& p, double t_abs) {
  const double t = t_abs - p.start_time;
  if (!p.enabled || p.cycles <= 0 || t <= 0.0) return p.T0;
  const double L = p.cycle_time();
  if (t >= p.cycles * L) return p.T0;
  const double tau = std::fmod(t, L);
  const double dT = p.T1 - p.T0;
  if (tau < p.heat_time) return p.T0 + dT * (tau / p.heat_time);
  if (tau < p.heat_time + p.hold_time) return p.T1;
  if (tau < p.heat_time + p.hold_time + p.cool_time)
    return p.T1 - dT * ((tau - p.heat_time - p.hold_time) / p.cool_time);
  return p.T0;
}

int cycle_index(const ThermalProtocol& p, double t) {
  if (!p.enabled || p.cycles <= 0) return 0;
  const int k = static_cast<int>(std::floor((t - p.start_time) / p.cycle_time()));
  return k < 0 ? 0 : (k > p.cycles ? p.cycles : k);
}

ThermalScales thermal_scales(const ThermalProtocol& p, const Effects& e, double t) {
  ThermalScales s;
  s.T = temperature(p, t);
  if (p.enabled && e.particle_expansion) s.s_p = 1.0 + p.alpha_p * (s.T - p.T0);
  if (p.enabled && e.container_expansion) s.s_c = 1.0 + p.alpha_c * (s.T - p.T0);
  return s;
}

}  // namespace ratchet

#include "ratchet/run/cycle_clock.hpp"

#include <algorithm>
#include <cmath>

#include "ratchet/io/json_numbers.hpp"

namespace ratchet {

CycleClock::CycleClock(const SceneDef& scene, double t0, bool settling) : scene_(scene) {
  thermal_ = scene_.thermal.enabled && scene_.thermal.cycles > 0;
  settle_pending_ = settling;
  // The start of cycling is the first state with t >= start_time (within round-off):
  // the initial state when start_time is 0, or a packing (run/packing.hpp) that ends there.
  started_ = thermal_ && t0 >= scene_.thermal.start_time - kTimeRoundTol * scene_.dt;
  started_at_first_ = started_;
  t_prev_ = t0;
}

StageEnds CycleClock::stage_ends(double t_prev, double t) const {
  StageEnds e;
  const ThermalProtocol& p = scene_.thermal;
  const double L = p.cycle_time();
  const double a = t_prev - p.start_time, b = t - p.start_time;
  if (b <= 0.0 || a >= p.cycles * L) return e;
  const int k = std::max(0, static_cast<int>(std::floor(a / L)));
  const double base = k * L;
  const double eps = kStageMarkTol * scene_.dt;  // stage marks that fall on a step: round-off in t
  auto crossed = [&](double mark) { return a < base + mark - eps && b >= base + mark - eps; };
  e.heating = crossed(p.heat_time);
  e.cooling = crossed(p.heat_time + p.hold_time + p.cool_time);
  e.cycle = crossed(L);
  return e;
}

nlohmann::json CycleClock::save() const {
  return {{"started", started_}, {"started_at_first", started_at_first_}, {"settle_pending", settle_pending_},
          {"t_prev", json_number(t_prev_)}, {"cycles_reached", cycles_reached_}};
}

void CycleClock::restore(const nlohmann::json& j) {
  started_ = j.at("started").get<bool>();
  started_at_first_ = j.at("started_at_first").get<bool>();
  settle_pending_ = j.at("settle_pending").get<bool>();
  t_prev_ = number_from_json(j.at("t_prev"));
  cycles_reached_ = j.at("cycles_reached").get<int>();
}

ClockTick CycleClock::tick(double t, bool settling) {
  ClockTick k;
  k.t = t;
  k.settling = settling;
  if (!thermal_) return k;
  // scene_.thermal is read at each tick: its start_time moves when a settle section's
  // stage ends (World::end_settle_stage).
  const ThermalProtocol& p = scene_.thermal;
  k.t_prev = t_prev_;
  if (settle_pending_ && !settling) {
    settle_pending_ = false;
    k.settle_ended = true;
  }
  k.before_cycling = !started_;
  // A state a few ulps below start_time reaches the mark, and so would the next step:
  // the start is taken once.
  if (!started_ && t >= p.start_time - kTimeRoundTol * scene_.dt) {
    started_ = true;
    k.cycling_starts = true;
  }
  const double tc = t - p.start_time;
  if (tc > 0.0 && tc <= p.cycles * p.cycle_time() + kStageMarkTol * scene_.dt) {
    // Clamped: t can land a few ulps past start_time or the end of the last cycle.
    k.cycle = std::max(
        0, std::min(p.cycles - 1, static_cast<int>(std::floor((tc - kStageMarkTol * scene_.dt) / p.cycle_time()))));
    cycles_reached_ = std::max(cycles_reached_, k.cycle + 1);
    k.ends = stage_ends(t_prev_, t);
  }
  t_prev_ = t;
  return k;
}

}  // namespace ratchet

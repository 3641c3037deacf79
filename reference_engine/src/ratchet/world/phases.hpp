// The phases of one time step, in order (docs/method.md, "The step"), and
// their timers. The step function in world.cpp calls them in this order.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>

namespace ratchet {

enum class Phase : int {
  FreeVelocity = 0,  // 1. v_free = v + h g
  Thermal,           // 2. T(t+h), s_p, s_c and their rates
  Detect,            // 3. broad + narrow phase
  Solve,             // 4. Delassus blocks, warm start, non-linear Gauss-Seidel
  Integrate,         // 5. positions, orientations, new scales
  KeepImpulses,      // 6. impulses kept for the next step's warm start
  Observe,           // 7. wall forces and the active contact count (observables are computed after the step, observe/)
  Count
};

constexpr std::array<const char*, static_cast<int>(Phase::Count)> kPhaseNames = {
    "free_velocity", "thermal", "detect", "solve", "integrate", "keep_impulses", "observe"};

struct PhaseTimers {
  std::array<double, static_cast<int>(Phase::Count)> seconds{};      // accumulated wall time
  std::array<std::int64_t, static_cast<int>(Phase::Count)> calls{};  // times the phase ran
  std::array<double, static_cast<int>(Phase::Count)> last_step{};    // wall time in the last step

  double& last(Phase p) { return last_step[static_cast<int>(p)]; }
};

// Times one phase: RAII, adds to the phase's counters on destruction.
class PhaseTimer {
 public:
  PhaseTimer(PhaseTimers& t, Phase p) : t_(t), p_(static_cast<int>(p)), start_(std::chrono::steady_clock::now()) {}
  ~PhaseTimer() {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    t_.seconds[p_] += s;
    t_.last_step[p_] = s;
    ++t_.calls[p_];
  }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  PhaseTimers& t_;
  int p_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace ratchet

// What a run finds wrong but survives (run.json "warnings", docs/output-format.md):
// steps stopped at the solver's cap, bodies or walls that move farther than the contact
// margin in one step, particles of the generator drawn again. Counted after every step;
// kept in a checkpoint so that a resumed run reports what the whole run saw.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/world/world.hpp"

namespace ratchet {

class RunWarnings {
 public:
  RunWarnings() = default;
  explicit RunWarnings(const nlohmann::json& saved);  // a checkpoint's record (save())
  nlohmann::json save() const;

  // After every step; `s_c_before` is the container scale before it. Returns true at
  // the first step stopped at the cap, which the runner reports at once.
  bool after_step(const World& world, double s_c_before);

  // The warnings of the run so far, as sentences; `travel` ones are also on stderr.
  nlohmann::json sentences(const World& world) const;

 private:
  std::int64_t first_capped_ = -1;
  double first_capped_t_ = 0.0, first_capped_residual_ = 0.0;
  // A body that moves more than the contact margin in one step can meet a contact only
  // after it has overlapped (docs/scene-format.md, solver.contact_margin).
  std::int64_t first_fast_ = -1, fast_steps_ = 0;
  double fastest_travel_ = 0.0;
  // The same for a wall, along its normal, as the container scale changes.
  std::int64_t first_fast_wall_ = -1, fast_wall_steps_ = 0;
  double fastest_wall_travel_ = 0.0;
};

// A thermal protocol that leaves the container less room relative to the particles than
// the bed was poured in (s_c / s_p below 1 at T1; both scales are linear in T): the bed
// must rise out of the container or jam, which rigid contacts cannot do quietly. Empty
// when there is no such squeeze (every ratio alpha_c / alpha_p >= 1 of the paper).
std::string squeeze_warning(const SceneDef& scene);

// The largest distance a body's centre moved in the last step (|v| h of the free bodies).
double largest_body_travel(const World& world);

// The largest distance an expanding wall moved along its normal when the container
// scale went from s_c_before to the current one: |Δs_c n·(p - c)|.
double largest_wall_travel(const World& world, double s_c_before);

}  // namespace ratchet

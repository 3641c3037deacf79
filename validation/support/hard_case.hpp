// What the hard cases share (validation/hard_cases_test.cpp, hard_thermal_test.cpp;
// docs/validation.md s. 9): a scene built in the test, run with run_world while the
// energy, overlap and solver record are watched, and the checks every case makes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"

namespace ratchet::hard_case {

struct Outcome {
  bool failed = false;
  std::string error;
  double ke_max = 0.0;
  double ke_end = 0.0;
  double overlap_max = 0.0;
  double overlap_end = 0.0;     // deepest overlap of the last step
  double side_force_max = 0.0;  // largest total normal force on the side walls
  double e0 = 0.0;       // sum m g z_i(0) of the free bodies (floor at z = 0) + initial KE
  double r_min = 1e300;  // smallest bounding radius of a free body
  double mass = 0.0;     // of the free bodies
  double e_excess = -1e300;  // max over the steps of KE + sum m g z - E0: mechanical energy gained
  std::int64_t steps = 0, capped_seen = 0, unconverged = 0, steps_with_contacts = 0, jammed = 0;
  nlohmann::json warnings = nlohmann::json::array();
};

// Runs the scene to its end (a RunError is caught and recorded as `failed`), watching
// every step; `inspect` sees the built scene first, `watch` every step after the runner.
Outcome run_scene(const nlohmann::json& j, const std::function<void(const SceneDef&)>& inspect = {},
                  const std::function<void(const World&)>& watch = {});

// A run warning contains `text`.
bool warned(const Outcome& o, const std::string& text);

// Recorded checks: the run completed; its mechanical energy never rose above E0 by more
// than one capped relaxation per body.
bool check_completed(const std::string& name, const Outcome& o);
bool check_energy_gain(const std::string& name, const Outcome& o);

// A cone of 8 segments, apothem 5, opening 2 degrees: 9 lattice sites per layer at the
// default spacing; `count` generated polyhedra of 12 vertices, seed 3, h = 0.004, 7 time units.
nlohmann::json pour_scene(const std::string& name, int count);

}  // namespace ratchet::hard_case

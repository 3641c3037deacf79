// The points of a sweep (docs/sweeps.md, "The sweep file"): the cartesian product of
// a "grid", or an explicit list of "points". Part of reading a sweep file (run/sweep.hpp).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ratchet {

// The points of the sweep file `sweep` (read from `source`), each one value per key of
// `keys` (set here, in sorted byte order):
// - "grid": {"dotted.path": [values ...], ...}: every combination, like an odometer,
//   the last key fastest;
// - "points": [{"dotted.path": value, ...}, ...]: the points in their order, each with
//   the same keys, no two the same;
// - neither: one point with no keys.
// Throws SceneError naming `source` and the field (grid.<key>, points, points[i]) for
// a malformed one, or when both are given.
std::vector<std::vector<nlohmann::json>> sweep_points(const nlohmann::json& sweep, const std::string& source,
                                                      std::vector<std::string>& keys);

}  // namespace ratchet

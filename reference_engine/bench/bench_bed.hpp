// The scene of step_bench's beds: N of the paper's polyhedra (20 vertices on an ellipsoid
// 1 : 0.95 : 0.9, r in [0.5, 1], mu = 0.5) released from a lattice into a 16-sided
// cylinder whose radius grows with sqrt(N) (r_c = 5 sqrt(N / 250)), so the bed height
// (about 5.5) stays the same. Shared by step_bench and bed_trace.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace ratchet::bench {

inline double cylinder_radius(int n) { return 5.0 * std::sqrt(static_cast<double>(n) / 250.0); }

// criterion: solver.criterion, written only when not the default (the cache key hashes
// the scene, so the cached beds stay valid).
inline nlohmann::json bed_scene(int n, double dt, double tolerance, int max_iterations,
                                const char* criterion = nullptr) {
  nlohmann::json j{
      {"name", "step_bench_" + std::to_string(n)},
      {"seed", 12345},
      {"time", {{"dt", dt}, {"duration", 1000.0}}},
      {"solver", {{"tolerance", tolerance}, {"max_iterations", max_iterations}, {"warm_start", true}}},
      {"materials", {{"friction", 0.5}, {"wall_friction", 0.5}}},
      {"container", {{"type", "cone"}, {"bottom_radius", cylinder_radius(n)}, {"opening_angle_deg", 0}, {"segments", 16}}},
      {"particles",
       {{"generate",
         {{"count", n}, {"shape", "polyhedron"}, {"vertices", 20}, {"radius_range", {0.5, 1.0}}, {"spacing", 2.3}}}}}};
  if (criterion != nullptr) j["solver"]["criterion"] = criterion;
  return j;
}

}  // namespace ratchet::bench

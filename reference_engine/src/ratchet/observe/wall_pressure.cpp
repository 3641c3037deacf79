#include "ratchet/observe/wall_pressure.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "ratchet/observe/bed_geometry.hpp"

namespace ratchet {
namespace {

[[noreturn]] void fail(const char* where, const std::string& why) {
  throw std::invalid_argument(std::string(where) + ": " + why);
}

// The lateral area formula, unchecked: N trapezoids of mean width (a0 + a1) tan(pi/N)
// and slant height H / cos(theta). The `pressure` column depends on its operation
// order bit for bit: keep it.
double lateral_area(double a0, double opening_angle_deg, int segments, double height) {
  const double theta = opening_angle_deg * M_PI / 180.0;
  const double a1 = a0 + height * std::tan(theta);
  return segments * (a0 + a1) * std::tan(M_PI / segments) * height / std::cos(theta);
}

}  // namespace

double frustum_side_area(double bottom_apothem, double opening_angle_deg, int segments, double height) {
  constexpr const char* where = "frustum_side_area";
  if (segments < 3) fail(where, "need at least 3 segments, got " + std::to_string(segments));
  if (!std::isfinite(bottom_apothem) || !(bottom_apothem > 0.0)) fail(where, "bottom apothem must be positive and finite");
  if (!std::isfinite(height) || height < 0.0) fail(where, "height must be >= 0 and finite");
  if (!std::isfinite(opening_angle_deg) || !(std::abs(opening_angle_deg) < 90.0))
    fail(where, "opening angle must lie in (-90, 90) degrees");
  const double theta = opening_angle_deg * M_PI / 180.0;
  if (bottom_apothem + height * std::tan(theta) < 0.0)
    fail(where, "the frustum closes below the given height (negative top apothem)");
  return lateral_area(bottom_apothem, opening_angle_deg, segments, height);
}

double wetted_side_area(const SceneDef& scene, const State& state, double height) {
  const ContainerDef& c = scene.container;
  if (c.type != ContainerDef::Type::Cone || height <= 0.0) return 0.0;
  return lateral_area(state.s_c * c.bottom_radius, c.opening_angle_deg, c.segments, height);
}

double side_wall_pressure(const SceneDef& scene, const State& state, double side_force, double height) {
  const double area = wetted_side_area(scene, state, height);
  return area > 0.0 ? side_force / area : 0.0;
}

double side_wall_pressure(const SceneDef& scene, const State& state, double side_force) {
  return side_wall_pressure(scene, state, side_force, bed_height(scene, state));
}

WallLoad wall_load(const std::vector<double>& segment_force, double bottom_force, double bottom_apothem,
                   double opening_angle_deg, int segments, double height) {
  if (segment_force.size() != static_cast<std::size_t>(std::max(segments, 0)))
    fail("wall_load", "got " + std::to_string(segment_force.size()) + " segment forces for " +
                          std::to_string(segments) + " segments");
  WallLoad load;
  load.segment_force = segment_force;
  load.side_force = std::accumulate(segment_force.begin(), segment_force.end(), 0.0);
  load.bottom_force = bottom_force;
  load.wetted_area = frustum_side_area(bottom_apothem, opening_angle_deg, segments, height);
  load.pressure = load.wetted_area > 0.0 ? load.side_force / load.wetted_area : 0.0;
  return load;
}

std::vector<double> wall_stress_profile(const std::vector<double>& contact_z,
                                        const std::vector<double>& contact_normal_force, double bottom_apothem,
                                        double opening_angle_deg, int segments, double height, int bins) {
  constexpr const char* where = "wall_stress_profile";
  if (contact_z.size() != contact_normal_force.size())
    fail(where, "got " + std::to_string(contact_z.size()) + " heights but " +
                    std::to_string(contact_normal_force.size()) + " forces");
  if (bins < 1) fail(where, "need at least 1 band, got " + std::to_string(bins));
  if (!std::isfinite(height) || !(height > 0.0)) fail(where, "height must be positive and finite");
  // Validates the geometry once for the whole frustum.
  frustum_side_area(bottom_apothem, opening_angle_deg, segments, height);

  const double dz = height / bins;
  std::vector<double> force(static_cast<std::size_t>(bins), 0.0);
  for (std::size_t i = 0; i < contact_z.size(); ++i) {
    const double z = contact_z[i], f = contact_normal_force[i];
    if (!std::isfinite(z) || !std::isfinite(f)) fail(where, "contact " + std::to_string(i) + " is not finite");
    const double k = std::floor(z / dz);
    const int band = k < 0.0 ? 0 : k >= bins ? bins - 1 : static_cast<int>(k);
    force[static_cast<std::size_t>(band)] += f;
  }
  const double tan_theta = std::tan(opening_angle_deg * M_PI / 180.0);
  std::vector<double> stress(static_cast<std::size_t>(bins));
  for (int k = 0; k < bins; ++k) {
    const double area = frustum_side_area(bottom_apothem + k * dz * tan_theta, opening_angle_deg, segments, dz);
    stress[static_cast<std::size_t>(k)] = force[static_cast<std::size_t>(k)] / area;
  }
  return stress;
}

}  // namespace ratchet

// Wall pressure P(t) on the side of the truncated-cone container (paper s.3, Fig. 3;
// docs/method.md s. 10): total normal force on the N side segments divided by the
// wetted side area, the lateral area of the N-gon frustum from z = 0 to the bed height
// (the highest particle point). Also the vertical profile of side-wall stress. Pure
// functions of forces, container geometry and a state; the one frustum-area formula
// of the engine is here.
#pragma once

#include <vector>

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

struct WallLoad {
  std::vector<double> segment_force;  // normal force on each side segment
  double side_force = 0.0;            // sum of segment_force
  double bottom_force = 0.0;          // normal force on the floor
  double wetted_area = 0.0;           // frustum_side_area up to the bed height
  double pressure = 0.0;              // side_force / wetted_area (0 if the area is 0)
};

// Lateral area of a regular N-gon frustum whose apothem is a0 = bottom_apothem at
// z = 0 and a1 = a0 + H tan(theta) at z = H, theta = opening angle from the vertical:
// N trapezoids of parallel sides 2 a0 tan(pi/N), 2 a1 tan(pi/N) and slant height
// H / cos(theta), i.e. N (a0 + a1) tan(pi/N) H / cos(theta). height = 0 gives 0.
// Throws std::invalid_argument for segments < 3, bottom_apothem <= 0, height < 0,
// |theta| >= 90 deg, a negative top apothem or non-finite input.
double frustum_side_area(double bottom_apothem, double opening_angle_deg, int segments, double height);

// Fills a WallLoad: side_force = sum of segment_force, wetted_area =
// frustum_side_area(bottom_apothem, opening_angle_deg, segments, height), pressure =
// side_force / wetted_area, or 0 when the bed height (hence the area) is 0, as
// side_wall_pressure does. Throws std::invalid_argument as frustum_side_area, or if
// segment_force.size() != segments.
WallLoad wall_load(const std::vector<double>& segment_force, double bottom_force, double bottom_apothem,
                   double opening_angle_deg, int segments, double height);

// The wetted side area of the scene's cone at the state's container scale s_c:
// frustum_side_area(s_c bottom_radius, opening angle, segments, height). 0 without a
// cone or for height <= 0; never throws (a non-finite height gives a non-finite area).
double wetted_side_area(const SceneDef& scene, const State& state, double height);

// The `pressure` column of timeseries.csv: side_force (StepStats::wall_force_side)
// divided by wetted_side_area up to bed_height (observe/bed_geometry.hpp), or 0 when
// that area is not positive (no cone, empty bed).
double side_wall_pressure(const SceneDef& scene, const State& state, double side_force);
// The same with the bed height already known (a caller that also writes it).
double side_wall_pressure(const SceneDef& scene, const State& state, double side_force, double height);

// Vertical profile of side-wall stress: [0, height] is cut into `bins` bands of equal
// height dz = height / bins; band k gets the total normal force of the side-wall
// contacts with k dz <= z < (k+1) dz, divided by its own lateral area
// frustum_side_area(a0 + k dz tan(theta), theta, N, dz). Contacts below 0 or at or
// above `height` (allowed overlap, the topmost point itself) count in the nearest
// band, so sum_k profile[k] * area_k equals the total side force.
// Throws std::invalid_argument for mismatched array sizes, bins < 1, height <= 0,
// non-finite contact data, or geometry that frustum_side_area rejects.
std::vector<double> wall_stress_profile(const std::vector<double>& contact_z,
                                        const std::vector<double>& contact_normal_force, double bottom_apothem,
                                        double opening_angle_deg, int segments, double height, int bins);

}  // namespace ratchet

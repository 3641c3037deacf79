// Internals of the scene reader (scene.hpp), shared by its files:
//   scene_reader.cpp     the reading context: checked fields, errors, "did you mean"
//   scene_sections.cpp   the sections: effects, solver, materials, thermal, container,
//                        outputs, settle
//   scene_particles.cpp  the particles section: listed bodies and generated beds
//   scene_overrides.cpp  the --set overrides and the origin of each field's value
//   scene.cpp            the public entry points, the top level and the time section,
//                        and the order the sections are read in
// Private: included by those files only.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ratchet/scene/scene.hpp"
#include "ratchet/scene/scene_reader.hpp"

namespace ratchet::scene_detail {

// A plane normal or an orientation quaternion whose norm is below this is refused as
// zero: it has no direction to normalize to (input units; directions are O(1)).
constexpr double kZeroNorm = 1e-12;

// scene_sections.cpp
void read_effects(const Reader& r, const json& j, Effects& e);
void read_solver(const Reader& r, const json& j, SolverSettings& s);
void read_materials(const Reader& r, const json& j, Materials& m);
void read_thermal(const Reader& r, const json& j, ThermalProtocol& t);
void read_container(const Reader& r, const json& j, ContainerDef& c);
void read_outputs(const Reader& r, const json& j, SceneDef& s);  // after thermal: vtk_cycles needs its cycles
void read_settle(const Reader& r, const json& j, SceneDef& s);   // after thermal: settle needs a thermal section

// scene_particles.cpp: after materials (density) and container (a cone's lattice);
// the draws are seeded by s.seed.
void read_particles(const Reader& r, const json& j, SceneDef& s);

// scene_overrides.cpp: Reader::origin_of for a scene read from `path` (whose JSON was
// `file`) with `overrides` applied.
std::function<std::string(const std::string& field)> override_origin(json file, std::vector<std::string> overrides,
                                                                     std::string path);

}  // namespace ratchet::scene_detail

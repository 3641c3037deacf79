// The bodies of a scene as built, with their shapes (docs/output-format.md, "Bodies
// and shapes"): per body its kind, radius or shape index, pose and velocities in a
// given state, mass properties and fixed flag; per shape its body-frame vertices,
// faces, volume and inertia per unit density. A JSON document with a format version,
// written by `ratchet bodies` and, as DIR/bodies_shapes.json, by `ratchet run`, so
// that a run folder carries its shapes and scripts never regenerate a scene.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet {

constexpr int kBodiesFileVersion = 1;
constexpr const char* kBodiesFileFormat = "ratchet-bodies";
// The name of the file in a run folder.
constexpr const char* kBodiesFileName = "bodies_shapes.json";

// The document for `scene` with the poses and velocities of `state` (the world's state:
// the scene's initial bodies, or a packing's state). Keys in a fixed, documented order.
// Throws std::invalid_argument when the state's per-body arrays do not match the scene.
nlohmann::ordered_json bodies_document(const SceneDef& scene, const State& state);

// The document as text: one top-level key per line and one body or shape per line
// (compact), numbers in the shortest form that reads back to the same double.
std::string format_bodies_document(const nlohmann::ordered_json& doc);

// Writes the document atomically (`<path>.partial`, then a rename); throws
// std::runtime_error when the file cannot be written.
void write_bodies_file(const std::string& path, const SceneDef& scene, const State& state);

}  // namespace ratchet

// The public entry points of the scene reader (scene.hpp): the file, the top level,
// the time section, and the order the sections are read in (scene_detail.hpp lists
// the files that read them).
#include "ratchet/scene/scene.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <utility>

#include "ratchet/io/json_file.hpp"
#include "ratchet/scene/scene_detail.hpp"

namespace ratchet {

using nlohmann::json;
using namespace scene_detail;  // Reader and the section readers

std::string fnv1a_hex(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a 64-bit offset basis
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;  // FNV 64-bit prime
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

// Time steps of `span` at `dt`, refused (naming `field`) below one step and above
// kMaxSteps, where std::llround would leave the range of int64 (undefined behaviour).
constexpr double kMaxSteps = 1e15;  // 1e15 steps of even a single body take decades
std::int64_t step_count(const Reader& r, const std::string& field, double span, double dt, const json* value) {
  const double n = span / dt;
  if (!(n >= 0.5)) r.fail(field, "at least one time step (duration >= dt / 2)", value);
  if (!(n <= kMaxSteps)) r.fail(field, "at most 1e15 time steps (duration / time.dt)", value);
  return static_cast<std::int64_t>(std::llround(n));
}

SceneDef build_scene_with(const json& j, const std::string& source,
                          std::function<std::string(const std::string&)> origin_of) {
  json effective = j;
  Reader r{source, std::move(origin_of), &effective};
  r.object(j, "", {"name", "seed", "gravity", "time", "solver", "materials", "effects", "container",
                   "particles", "thermal", "outputs", "settle", "description"});
  SceneDef s;
  s.source = source;
  s.name = r.string(j, "", "name", "");
  if (s.name.empty()) r.fail("name", "a non-empty string", j.contains("name") ? &j.at("name") : nullptr);
  s.seed = static_cast<std::uint64_t>(r.integer(j, "", "seed", 1, 0, std::numeric_limits<long long>::max()));
  s.gravity = r.vec3(j, "", "gravity", s.gravity);
  // A missing section of settings reads as an empty one: its defaults (the same as
  // SceneDef's) go into the effective scene. A missing thermal, container or settle
  // section means "none", and stays missing.
  const json none = json::object();
  auto section = [&](const char* key) -> const json& { return j.contains(key) ? j.at(key) : none; };
  read_effects(r, section("effects"), s.effects);
  read_solver(r, section("solver"), s.solver);
  read_materials(r, section("materials"), s.materials);
  if (j.contains("thermal")) read_thermal(r, j.at("thermal"), s.thermal);
  if (j.contains("container")) read_container(r, j.at("container"), s.container);
  read_outputs(r, section("outputs"), s);
  if (j.contains("settle")) read_settle(r, j.at("settle"), s);
  const json& time = r.required(j, "", "time", "an object {dt, duration}");
  r.object(time, "time", {"dt", "duration"});
  s.dt = r.positive(time, "time", "dt", s.dt);
  std::string span_field = "time.duration";  // the field an error about the step count names
  const json* span_value = nullptr;
  if (time.contains("duration")) {
    s.duration = r.positive(time, "time", "duration", 0.0);
    span_value = &time.at("duration");
  } else if (s.thermal.enabled && s.thermal.cycles > 0) {
    s.duration = s.thermal.start_time + s.thermal.cycles * s.thermal.cycle_time();
    span_field = "thermal";  // derived: named by the protocol's fields
  } else {
    r.fail("time.duration", "a positive duration (or a thermal protocol with cycles to derive it from)");
  }
  r.fill("time", "duration", s.duration);  // derived from the protocol: written out
  s.steps = step_count(r, span_field, s.duration, s.dt, span_value);
  if (s.settle.enabled) {
    // Times written in the scene count from the end of the settle stage; until it is
    // known, assume the latest (SettleDef).
    s.settle.rest_time = s.thermal.start_time;
    s.settle.run_time = s.duration;
    s.thermal.start_time = s.settle.max_time + s.settle.rest_time;
    s.duration = s.settle.max_time + s.settle.run_time;
    s.steps = step_count(r, "settle.max_time", s.settle.max_time, s.dt, &j.at("settle").at("max_time")) + s.steps;
  }
  read_particles(r, r.required(j, "", "particles", "an object {generate and/or bodies}"), s);
  s.as_run = j;
  s.hash = fnv1a_hex(j.dump());
  s.effective = std::move(effective);
  return s;
}

}  // namespace

SceneDef build_scene(const json& j, const std::string& source) { return build_scene_with(j, source, nullptr); }

SceneDef load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  json j;
  try {
    j = read_json_file(path, "scene file");
  } catch (const JsonFileError& e) {
    throw SceneError(e.what());
  }
  json file = j;
  for (const std::string& o : overrides) apply_override(j, o, path);
  return build_scene_with(j, path, scene_detail::override_origin(std::move(file), overrides, path));
}

}  // namespace ratchet

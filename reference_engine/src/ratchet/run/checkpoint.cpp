#include "ratchet/run/checkpoint.hpp"

#include <filesystem>

#include "ratchet/io/json_numbers.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

namespace {

constexpr const char* kKind = "ratchet run checkpoint";

}  // namespace

nlohmann::json progress_json(const WorldProgress& p) {
  nlohmann::json seconds = nlohmann::json::array(), calls = nlohmann::json::array();
  for (std::size_t k = 0; k < p.timers.seconds.size(); ++k) {
    seconds.push_back(json_number(p.timers.seconds[k]));
    calls.push_back(p.timers.calls[k]);
  }
  return {{"settling", p.settling},
          {"start_time", json_number(p.start_time)},
          {"duration", json_number(p.duration)},
          {"steps", p.steps},
          {"tangential_solves", p.totals.tangential_solves},
          {"total_iterations", p.totals.total_iterations},
          {"unconverged_steps", p.totals.unconverged_steps},
          {"jammed_steps", p.totals.jammed_steps},
          {"relaxed_steps", p.totals.relaxed_steps},
          {"phase_seconds", seconds},
          {"phase_calls", calls}};
}

WorldProgress progress_from_json(const nlohmann::json& j) {
  WorldProgress p;
  p.settling = j.at("settling").get<bool>();
  p.start_time = number_from_json(j.at("start_time"));
  p.duration = number_from_json(j.at("duration"));
  p.steps = j.at("steps").get<std::int64_t>();
  p.totals.tangential_solves = j.at("tangential_solves").get<std::int64_t>();
  p.totals.total_iterations = j.at("total_iterations").get<std::int64_t>();
  p.totals.unconverged_steps = j.at("unconverged_steps").get<std::int64_t>();
  p.totals.jammed_steps = j.at("jammed_steps").get<std::int64_t>();
  p.totals.relaxed_steps = j.at("relaxed_steps").get<std::int64_t>();
  const auto& seconds = j.at("phase_seconds");
  const auto& calls = j.at("phase_calls");
  if (seconds.size() != p.timers.seconds.size() || calls.size() != p.timers.calls.size())
    throw std::runtime_error("phase timers of another engine (" + std::to_string(seconds.size()) + " phases)");
  for (std::size_t k = 0; k < p.timers.seconds.size(); ++k) {
    p.timers.seconds[k] = number_from_json(seconds[k]);
    p.timers.calls[k] = calls[k].get<std::int64_t>();
  }
  return p;
}

void write_checkpoint(const std::string& dir, const World& world, const nlohmann::json& run) {
  const SceneDef& s = world.scene();
  StateFile f;
  f.key = s.hash;
  f.meta = {{"kind", kKind},
            {"engine_version", RATCHET_VERSION},
            {"engine", engine_record()},
            {"scene_file", s.source},
            {"scene", s.as_run},
            {"world", progress_json(world.progress())},
            {"run", run}};
  f.state = world.state();
  write_state_file(dir + "/" + kCheckpointFileName, f);
}

ResumePoint read_checkpoint(const std::string& dir) {
  ResumePoint p;
  p.path = dir + "/" + kCheckpointFileName;
  if (!std::filesystem::is_regular_file(p.path))
    throw StateFileError(p.path + ": no checkpoint to resume from (a run writes one every outputs.checkpoint_every "
                                  "steps and when SIGINT or SIGTERM stops it)");
  StateFile f = read_state_file(p.path);
  const nlohmann::json& m = f.meta;
  if (m.value("kind", "") != kKind) throw StateFileError(p.path + ": not a run checkpoint (a packing?)");
  const std::string version = m.value("engine_version", "");
  if (version != RATCHET_VERSION)
    throw StateFileError(p.path + ": written by engine version " + version + ", this is " + RATCHET_VERSION +
                         ": only the same engine continues a run bit for bit");
  if (const std::string other = other_engine(m.value("engine", nlohmann::json())); !other.empty())
    throw StateFileError(p.path + ": " + other + ": only the same engine continues a run bit for bit");
  try {
    p.scene = build_scene(m.at("scene"), m.at("scene_file").get<std::string>());
    if (p.scene.hash != f.key)
      throw StateFileError(p.path + ": the scene stored in the checkpoint hashes to " + p.scene.hash + ", its key is " +
                           f.key);
    if (f.state.x.size() != p.scene.bodies.size())
      throw StateFileError(p.path + ": state of " + std::to_string(f.state.x.size()) + " bodies, the scene has " +
                           std::to_string(p.scene.bodies.size()));
    p.progress = progress_from_json(m.at("world"));
    p.run = m.at("run");
  } catch (const nlohmann::json::exception& e) {
    throw StateFileError(p.path + ": damaged checkpoint record: " + e.what());
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const StateFileError*>(&e) || dynamic_cast<const SceneError*>(&e)) throw;
    throw StateFileError(p.path + ": damaged checkpoint record: " + e.what());
  }
  p.state = std::move(f.state);
  return p;
}

void resume_world(World& world, const ResumePoint& point) {
  world.mutable_state() = point.state;
  world.restore_progress(point.progress);
}

}  // namespace ratchet

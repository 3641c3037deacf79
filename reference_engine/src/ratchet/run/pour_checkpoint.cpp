#include "ratchet/run/pour_checkpoint.hpp"

#include <filesystem>

#include "ratchet/io/state_file.hpp"
#include "ratchet/run/checkpoint.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/run_output.hpp"

namespace ratchet {

namespace {
constexpr const char* kKind = "ratchet pour checkpoint";
}  // namespace

std::string pour_checkpoint_path(const std::string& packing_path) { return packing_path + ".pour-checkpoint"; }

PourCheckpointing pour_checkpointing(const std::string& packing_path, const SceneDef& scene) {
  return {pour_checkpoint_path(packing_path), scene.outputs.checkpoint_every};
}

void remove_pour_checkpoint(const PourCheckpointing& checkpoints) {
  if (checkpoints.path.empty()) return;
  std::error_code gone;
  std::filesystem::remove(checkpoints.path, gone);
}

void write_pour_checkpoint(const std::string& path, const World& world, const nlohmann::json& monitor) {
  const SceneDef& s = world.scene();
  StateFile f;
  f.key = packing_key(s);
  f.meta = {{"kind", kKind},
            {"engine_version", RATCHET_VERSION},
            {"engine", engine_record()},
            {"packing_scene", packing_scene(s.as_run)},
            {"world", progress_json(world.progress())},
            {"settle_monitor", monitor}};
  f.state = world.state();
  write_state_file(path, f);
}

nlohmann::json resume_pour(const std::string& path, World& world, std::string* why_not) {
  auto refuse = [&](const std::string& why) {
    if (why_not != nullptr) *why_not = path + ": " + why;
    return nlohmann::json();
  };
  if (!std::filesystem::exists(path)) return nlohmann::json();
  StateFile f;
  try {
    f = read_state_file(path);
  } catch (const StateFileError& e) {
    if (why_not != nullptr) *why_not = e.what();
    return nlohmann::json();
  }
  const nlohmann::json& m = f.meta;
  if (m.value("kind", "") != kKind) return refuse("not a pour checkpoint");
  if (m.value("engine_version", "") != RATCHET_VERSION)
    return refuse("written by engine version " + m.value("engine_version", "") + ", this is " + RATCHET_VERSION);
  if (const std::string other = other_engine(m.value("engine", nlohmann::json())); !other.empty()) return refuse(other);
  const std::string key = packing_key(world.scene());
  if (f.key != key) return refuse("the pour of packing " + f.key + ", this one is " + key);
  if (f.state.x.size() != world.scene().bodies.size())
    return refuse("state of " + std::to_string(f.state.x.size()) + " bodies, the scene has " +
                  std::to_string(world.scene().bodies.size()));
  try {
    const WorldProgress progress = progress_from_json(m.at("world"));
    const nlohmann::json monitor = m.at("settle_monitor");
    const SettleMonitor readable(world, monitor);  // throws on a damaged record, before the world changes
    (void)readable;
    world.mutable_state() = std::move(f.state);
    world.restore_progress(progress);
    return monitor;
  } catch (const std::exception& e) {
    return refuse(std::string("damaged record: ") + e.what());
  }
}

}  // namespace ratchet

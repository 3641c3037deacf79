// The pour's checkpoint (run/pour_checkpoint.hpp): a pour stopped by a request, or
// "killed" (its checkpoint copied as it stood on disk at some step, as SIGKILL would leave
// it), goes on from its checkpoint to the same state, bit for bit, as the pour that never
// stopped; a checkpoint of another pour, or a damaged one, is not used and says why; a
// pour that fails leaves none. scripts/tests/test_resume.py does the same with real
// signals on `ratchet pack` and `ratchet sweep`.
#include "ratchet/run/pour_checkpoint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "../support/test_files.hpp"
#include "ratchet/io/state_file.hpp"
#include "ratchet/run/packing.hpp"
#include "ratchet/run/stop_request.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;
using test::fresh_dir;

// 14 polyhedra poured into a cone and settled by a settle section (KE <= 1e-4 of its
// peak, at about step 1350): under a second.
json bed(int seed = 5) {
  json j = json::parse(R"({
    "name": "pour", "time": {"dt": 0.005},
    "solver": {"tolerance": 1e-4, "max_iterations": 100},
    "container": {"type": "cone", "bottom_radius": 2.5, "opening_angle_deg": 4.0},
    "particles": {"generate": {"count": 14, "shape": "polyhedron", "vertices": 10, "radius_range": [0.3, 0.5]}},
    "settle": {"ke_ratio": 1e-4, "max_time": 10.0},
    "thermal": {"start_time": 0.25, "heat_time": 0.5, "hold_time": 0.25, "cool_time": 0.5, "cycles": 1,
                "alpha_p": 1e-3, "alpha_c": 1e-2}
  })");
  j["seed"] = seed;
  return j;
}

// The state's bytes as a state file holds them (every body's pose, velocity, scale, the
// kept impulses, planes and manifolds).
std::string state_bytes(const World& w) { return encode_state_file(StateFile{"k", json::object(), w.state()}); }

struct Poured {
  std::string state;
  json settle;
};

Poured pour_through(int seed = 5) {
  World w(build_scene(bed(seed), "pour.json"));
  const json settle = settle_world(w);
  return {state_bytes(w), settle};
}

TEST(PourCheckpoint, AStoppedPourGoesOnToTheSameState) {
  const Poured through = pour_through();
  const fs::path dir = fresh_dir("pour_stopped");
  const PourCheckpointing cp{(dir / "p.state.pour-checkpoint").string(), 0};
  World first(build_scene(bed(), "pour.json"));
  clear_stop_request();
  try {
    (void)settle_world(first, [](const World& w) { if (w.state().step == 400) request_stop(SIGTERM); }, cp);
    clear_stop_request();
    FAIL() << "the pour was not stopped";
  } catch (const RunInterrupted& e) {
    clear_stop_request();
    EXPECT_EQ(e.signal, SIGTERM);
    EXPECT_THAT(e.what(), HasSubstr("the pour stopped by SIGTERM at step 400"));
    EXPECT_THAT(e.what(), HasSubstr(cp.path));
  }
  ASSERT_TRUE(fs::exists(cp.path));
  World second(build_scene(bed(), "pour.json"));
  std::string note;
  const json settle = settle_world(second, {}, cp, [&](const std::string& s) { note = s; });
  EXPECT_THAT(note, HasSubstr("resumes the pour from " + cp.path + " at step 400"));
  EXPECT_EQ(state_bytes(second), through.state);
  EXPECT_EQ(settle, through.settle);  // the monitor went on as it was: peak, step, t
  EXPECT_TRUE(fs::exists(cp.path));   // the caller removes it once the packing is written
  fs::remove_all(dir);
}

TEST(PourCheckpoint, AKilledPourGoesOnFromItsLastPeriodicCheckpoint) {
  const Poured through = pour_through();
  const fs::path dir = fresh_dir("pour_killed");
  const PourCheckpointing cp{(dir / "p.state.pour-checkpoint").string(), 300};
  const fs::path left = dir / "as_left_at_step_700";
  World first(build_scene(bed(), "pour.json"));
  const json settle_first = settle_world(first, [&](const World& w) {
    if (w.state().step == 700) fs::copy_file(cp.path, left);  // on disk then: step 600's
  }, cp);
  EXPECT_EQ(state_bytes(first), through.state);  // checkpoints change nothing of the pour
  fs::rename(left, cp.path);
  World second(build_scene(bed(), "pour.json"));
  std::string note;
  const json settle = settle_world(second, {}, cp, [&](const std::string& s) { note = s; });
  EXPECT_THAT(note, HasSubstr("at step 600"));
  EXPECT_EQ(state_bytes(second), through.state);
  EXPECT_EQ(settle, through.settle);
  fs::remove_all(dir);
}

TEST(PourCheckpoint, ACheckpointOfAnotherPourIsNotUsed) {
  const fs::path dir = fresh_dir("pour_other");
  const PourCheckpointing cp{(dir / "p.state.pour-checkpoint").string(), 0};
  World seed5(build_scene(bed(5), "pour.json"));
  for (int i = 0; i < 200; ++i) seed5.step();
  write_pour_checkpoint(cp.path, seed5, json{{"peak", 1.0}, {"ke", 1.0}, {"t", 1.0}, {"step", 200},
                                            {"below", false}, {"done", false}});
  World seed6(build_scene(bed(6), "pour.json"));
  std::string note;
  (void)settle_world(seed6, {}, cp, [&](const std::string& s) { note = s; });
  EXPECT_THAT(note, HasSubstr("not resuming the pour: " + cp.path + ": the pour of packing " + packing_key(seed5.scene()) +
                              ", this one is " + packing_key(seed6.scene())));
  EXPECT_THAT(note, HasSubstr("pouring from the start"));
  EXPECT_EQ(state_bytes(seed6), pour_through(6).state);
  fs::remove_all(dir);
}

TEST(PourCheckpoint, ADamagedCheckpointIsNotUsed) {
  const fs::path dir = fresh_dir("pour_damaged");
  const PourCheckpointing cp{(dir / "p.state.pour-checkpoint").string(), 0};
  World w(build_scene(bed(), "pour.json"));
  for (int i = 0; i < 100; ++i) w.step();
  write_pour_checkpoint(cp.path, w, json{{"peak", 1.0}, {"ke", 1.0}, {"t", 0.5}, {"step", 100},
                                         {"below", false}, {"done", false}});
  std::string bytes = test::read_text(cp.path);
  bytes[bytes.size() / 2] ^= 0x5a;  // the checksum no longer holds
  std::ofstream(cp.path, std::ios::binary) << bytes;
  World fresh(build_scene(bed(), "pour.json"));
  std::string note;
  (void)settle_world(fresh, {}, cp, [&](const std::string& s) { note = s; });
  EXPECT_THAT(note, HasSubstr("not resuming the pour: " + cp.path));
  EXPECT_EQ(state_bytes(fresh), pour_through().state);
  fs::remove_all(dir);
}

TEST(PourCheckpoint, APourThatFailsLeavesNoCheckpoint) {
  const fs::path dir = fresh_dir("pour_failed");
  const PourCheckpointing cp{(dir / "p.state.pour-checkpoint").string(), 50};
  json strict = bed();
  strict["settle"] = {{"ke_ratio", 1e-300}, {"max_time", 1.0}};  // 200 steps, never settled
  World w(build_scene(strict, "strict.json"));
  bool written = false;
  EXPECT_THROW((void)settle_world(w, [&](const World&) { written = written || fs::exists(cp.path); }, cp),
               SettleError);
  EXPECT_TRUE(written);               // periodic checkpoints were there during the pour
  EXPECT_FALSE(fs::exists(cp.path));  // and a pour that fails again from them is not kept
  fs::remove_all(dir);
}

}  // namespace
}  // namespace ratchet

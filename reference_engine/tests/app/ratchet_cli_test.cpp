// The command-line program, run as a user would: exit codes, messages, and that a
// rejected scene leaves no output behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct Result {
  int status;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const std::string cmd = std::string(RATCHET_BIN) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), pipe.get()) != nullptr) out += buf.data();
  const int raw = pclose(pipe.release());
  return {WEXITSTATUS(raw), out};
}

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() /
                     (std::string("ratchet_cli_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

const char* kScene = R"({
  "name": "cli", "time": {"dt": 0.01, "duration": 0.5},
  "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
  "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 1]}]}
})";

TEST(RatchetCli, RunWritesCompleteOutputs) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  const Result r = run("run " + (d / "s.json").string() + " --out " + (d / "out").string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"timeseries.csv", "bodies.csv", "run.json"}) EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
  for (const auto& e : fs::directory_iterator(d / "out")) EXPECT_NE(e.path().extension(), ".partial");
  std::ifstream in(d / "out" / "run.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("\"status\": \"completed\""));
  fs::remove_all(d);
}

TEST(RatchetCli, MalformedSceneFailsBeforeAnyOutput) {
  const fs::path d = scratch();
  std::string bad = kScene;
  bad.replace(bad.find("\"radius\": 0.5"), 13, "\"radius\": -0.5");
  write(d / "bad.json", bad);
  const Result r = run("run " + (d / "bad.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("bad.json"));
  EXPECT_THAT(r.output, HasSubstr("particles.bodies[0].radius"));
  EXPECT_THAT(r.output, HasSubstr("positive"));
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

TEST(RatchetCli, InvalidJsonAndUnknownOverrideAreRefused) {
  const fs::path d = scratch();
  write(d / "broken.json", "{\"name\": \"x\",, }");
  Result r = run("run " + (d / "broken.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("not valid JSON"));
  write(d / "s.json", kScene);
  r = run("run " + (d / "s.json").string() + " --out " + (d / "out").string() + " --set solver.tolerence=1");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("solver.tolerence"));
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

TEST(RatchetCli, ExplainListsPhasesAndWhySomeAreSkipped) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  const Result r = run("run --explain " + (d / "s.json").string() + " --set effects.friction=false");
  EXPECT_EQ(r.status, 0);
  EXPECT_THAT(r.output, HasSubstr("thermal        skip the scene has no thermal protocol"));
  EXPECT_THAT(r.output, HasSubstr("normal part only: effects.friction is off"));
  fs::remove_all(d);
}

// A sphere dropped onto a floor, settled until t = 0.3, then one short heating cycle.
const char* kThermalScene = R"({
  "name": "cli_thermal", "time": {"dt": 0.01},
  "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0], "expands": true}]},
  "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.6]}]},
  "thermal": {"start_time": 0.3, "heat_time": 0.1, "cycles": 1}
})";

// The same sphere with a settle section: it lands (inelastic contact, KE 0) at
// t = 0.46, which ends the settle stage; the cycle (0.2) starts 0.05 later.
const char* kSettleScene = R"({
  "name": "cli_settle", "time": {"dt": 0.01},
  "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0], "expands": true}]},
  "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 0.6]}]},
  "thermal": {"start_time": 0.05, "heat_time": 0.1, "cycles": 1},
  "settle": {"ke_ratio": 1e-6, "max_time": 1.0}
})";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(RatchetCli, PackThenRunFromThePacking) {
  const fs::path d = scratch();
  write(d / "s.json", kThermalScene);
  const std::string scene = (d / "s.json").string(), packing = (d / "packs" / "p.state").string();
  Result r = run("pack " + scene + " --out " + packing + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(packing));
  EXPECT_FALSE(fs::exists(packing + ".partial"));
  // Another expansion coefficient has the same packing key.
  r = run("run " + scene + " --out " + (d / "out").string() + " --packing " + packing +
          " --set thermal.alpha_c=0.002 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string meta = slurp(d / "out" / "run.json");
  EXPECT_THAT(meta, HasSubstr("\"packing\": {"));
  EXPECT_THAT(meta, HasSubstr("\"reached\": null"));  // no settle section: no threshold
  EXPECT_EQ(slurp(d / "out" / "bodies.csv").substr(0, 100).find("\n0,0,"), std::string::npos);  // starts at the packing
  r = run("run --explain " + scene + " --packing " + packing);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("starts from the packing " + packing + " (step 29,"));
  fs::remove_all(d);
}

TEST(RatchetCli, SettleSectionEndsTheStageWhenTheBedIsAtRest) {
  const fs::path d = scratch();
  write(d / "s.json", kSettleScene);
  const std::string scene = (d / "s.json").string(), packing = (d / "p.state").string();
  Result r = run("run --explain " + scene);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("settles until KE <= 1e-06 x its peak (at most t = 1)"));
  r = run("pack " + scene + " --out " + packing);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("at t = 0.46"));
  r = run("run " + scene + " --out " + (d / "from_packing").string() + " --packing " + packing + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("run " + scene + " --out " + (d / "straight").string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* dir : {"from_packing", "straight"}) {
    const std::string meta = slurp(d / dir / "run.json");
    EXPECT_THAT(meta, HasSubstr("\"reached\": true")) << dir;
    EXPECT_THAT(meta, HasSubstr("\"steps\": 71")) << dir;  // 46 settling + 5 rest + 20 of the cycle
  }
  // Not at rest by max_time (still falling): the run stops with the reason and
  // nothing looks complete.
  r = run("run " + scene + " --out " + (d / "strict").string() + " --set settle.max_time=0.3 --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_THAT(r.output, HasSubstr(scene + ": the bed did not settle by settle.max_time = 0.3"));
  EXPECT_FALSE(fs::exists(d / "strict" / "run.json"));
  r = run("pack " + scene + " --out " + (d / "strict.state").string() + " --set settle.max_time=0.3 --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_FALSE(fs::exists(d / "strict.state"));
  fs::remove_all(d);
}

TEST(RatchetCli, PackingOfAnotherSceneOrDamagedIsRefusedBeforeAnyOutput) {
  const fs::path d = scratch();
  write(d / "s.json", kThermalScene);
  const std::string scene = (d / "s.json").string(), packing = (d / "p.state").string();
  ASSERT_EQ(run("pack " + scene + " --out " + packing + " --quiet").status, 0);
  Result r = run("run " + scene + " --out " + (d / "out").string() + " --packing " + packing +
                 " --set thermal.start_time=0.5");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr(packing + ": packing of a different scene"));
  EXPECT_THAT(r.output, HasSubstr("field 'thermal.start_time' is 0.3 in the packing's scene and 0.5 in this one"));
  EXPECT_FALSE(fs::exists(d / "out"));
  const std::string bytes = slurp(packing);
  std::ofstream(d / "cut.state", std::ios::binary) << bytes.substr(0, bytes.size() - 3);
  r = run("run " + scene + " --out " + (d / "out").string() + " --packing " + (d / "cut.state").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr((d / "cut.state").string() + ": truncated or corrupt state file"));
  EXPECT_FALSE(fs::exists(d / "out"));
  // No thermal section: nothing to settle, nothing written.
  write(d / "cold.json", kScene);
  r = run("pack " + (d / "cold.json").string() + " --out " + (d / "cold.state").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("cold.json: field 'thermal': expected a thermal section"));
  EXPECT_FALSE(fs::exists(d / "cold.state"));
  EXPECT_EQ(run("pack " + scene).status, 2);                        // no --out
  EXPECT_EQ(run("pack " + scene + " --out " + d.string()).status, 2);  // --out names a folder
  fs::remove_all(d);
}

TEST(RatchetCli, UsageErrors) {
  EXPECT_EQ(run("").status, 2);
  EXPECT_EQ(run("frobnicate").status, 2);
  EXPECT_EQ(run("run scene.json").status, 2);  // no --out
  EXPECT_EQ(run("--version").status, 0);
}

}  // namespace

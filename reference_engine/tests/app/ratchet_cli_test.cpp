// The command-line program, run as a user would: exit codes, messages, and that a
// rejected scene leaves no output behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/core/build_info.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

struct Result {
  int status;
  std::string output;  // stdout and stderr
};

// `redirect` chooses what is read: both streams (default), or one of them.
Result run(const std::string& args, const std::string& redirect = "2>&1") {
  const std::string cmd = std::string(RATCHET_BIN) + " " + args + " " + redirect;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), pipe.get()) != nullptr) out += buf.data();
  const int raw = pclose(pipe.release());
  return {WEXITSTATUS(raw), out};
}
Result stdout_of(const std::string& args) { return run(args, "2>/dev/null"); }
Result stderr_of(const std::string& args) { return run(args, "2>&1 >/dev/null"); }

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
  for (const char* f : {"timeseries.csv", "bodies.csv", "bodies_shapes.json", "run.json"})
    EXPECT_TRUE(fs::exists(d / "out" / f)) << f;
  for (const auto& e : fs::directory_iterator(d / "out")) EXPECT_NE(e.path().extension(), ".partial");
  std::ifstream in(d / "out" / "run.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("\"status\": \"completed\""));
  fs::remove_all(d);
}

// run.json's provenance (docs/output-format.md, "run.json"): the engine's commit and
// source hash, the date, the host, the command line word for word, and the scene with
// its defaults filled in (the seed, the solver's tolerance) beside the scene as run.
TEST(RatchetCli, RunJsonSaysWhichEngineWhenWhereAndHow) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  const Result r = run("run " + (d / "s.json").string() + " --out " + (d / "out").string() +
                       " --set outputs.timeseries_every=5 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(d / "out" / "run.json"));
  const std::string commit = j.at("engine").at("commit");
  // 40 hex digits (and "+modified" when the tree had changes), or "unknown" without git.
  EXPECT_TRUE(std::regex_match(commit, std::regex("([0-9a-f]{40}(\\+modified)?|unknown)"))) << commit;
  EXPECT_TRUE(std::regex_match(j.at("engine").at("source_hash").get<std::string>(), std::regex("[0-9a-f]{16}")));
  const nlohmann::json& p = j.at("provenance");
  EXPECT_TRUE(std::regex_match(p.at("date_utc").get<std::string>(),
                               std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")));
  EXPECT_FALSE(p.at("host").get<std::string>().empty());
  EXPECT_EQ(p.at("command_line"), nlohmann::json({RATCHET_BIN, "run", (d / "s.json").string(), "--out",
                                                  (d / "out").string(), "--set", "outputs.timeseries_every=5",
                                                  "--quiet"}));
  EXPECT_FALSE(j.at("scene").contains("seed"));  // as run: the file and the --set
  EXPECT_EQ(j.at("scene").at("outputs").at("timeseries_every"), 5);
  EXPECT_EQ(j.at("effective_scene").at("seed"), 1);
  EXPECT_EQ(j.at("effective_scene").at("solver").at("tolerance"), 1e-4);
  EXPECT_EQ(j.at("effective_scene").at("outputs").at("timeseries_every"), 5);
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

TEST(RatchetCli, AnUnreadableSceneSaysWhy) {
  const fs::path d = scratch();
  Result r = run("run " + (d / "absent.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("absent.json: cannot open the scene file (no such file)"));
  fs::create_directories(d / "folder.json");
  r = run("run " + (d / "folder.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("folder.json: cannot open the scene file (a folder, not a file)"));
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

TEST(RatchetCli, InvalidJsonAndUnknownOverrideAreRefused) {
  const fs::path d = scratch();
  write(d / "broken.json", "{\"name\": \"x\",, }");
  Result r = run("run " + (d / "broken.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("not valid JSON: parse error at line 1, column 14"));
  EXPECT_THAT(r.output, Not(HasSubstr("json.exception")));  // the library's tag says nothing to a user
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
  // The run folder's bodies file holds the state the run starts from: the packing's.
  EXPECT_THAT(slurp(d / "out" / "bodies_shapes.json"), HasSubstr("\n  \"step\": 29,\n"));
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
  Result r = stdout_of("");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("usage:"));  // on stdout
  r = run("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ratchet: unknown command 'frobnicate'"));
  EXPECT_EQ(run("run scene.json").status, 2);  // no --out
  r = run("run scene.json --out d --frob");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ratchet: unknown option '--frob'"));
  EXPECT_THAT(r.output, HasSubstr("ratchet run SCENE.json --out DIR"));  // the usage of the command follows
  r = run("pack scene.json --explain --out p.state");  // run's option, not pack's
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("unknown option '--explain'"));
  r = run("run scene.json --out");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ratchet: --out needs a value"));
  r = run("run a.json b.json --out d");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("more than one scene file given ('a.json', 'b.json')"));
  r = run("sweep a.json b.json --out d");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("more than one sweep file given"));
  r = run("sweep a.json");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("sweep needs SWEEP.json and --out DIR"));
}

// Options and the scene path in any order; --set takes one value, so the path after it
// stays the scene.
TEST(RatchetCli, OptionsInAnyOrder) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  const Result r = run("run --set effects.friction=false " + (d / "s.json").string() +
                       " --explain --set solver.warm_start=false");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("normal part only: effects.friction is off"));
  EXPECT_THAT(r.output, HasSubstr("keep_impulses  skip solver.warm_start is off"));
  fs::remove_all(d);
}

TEST(RatchetCli, HelpOfTheProgramAndOfEachCommandOnStdout) {
  for (const char* flag : {"--help", "-h", "help"}) {
    const Result r = stdout_of(flag);
    EXPECT_EQ(r.status, 0) << flag;
    for (const char* line : {"usage:", "ratchet run SCENE.json --out DIR", "ratchet pack SCENE.json --out FILE",
                             "ratchet bodies SCENE.json --out FILE.json",
                             "ratchet sweep SWEEP.json --out DIR [--jobs N]", "ratchet --version | -V | version"})
      EXPECT_THAT(r.output, HasSubstr(line)) << flag;
  }
  // Each command's help: its usage and every one of its options, on stdout, nothing on stderr.
  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"run", {"ratchet run SCENE.json --out DIR", "ratchet run --explain SCENE.json", "--out DIR", "--packing FILE",
               "--set key.path=value", "--explain", "--quiet", "--progress-every SECONDS"}},
      {"pack", {"ratchet pack SCENE.json --out FILE", "--out FILE", "--set key.path=value", "--quiet"}},
      {"bodies", {"ratchet bodies SCENE.json --out FILE.json", "--out FILE.json", "--set key.path=value", "--quiet"}},
      {"sweep", {"ratchet sweep SWEEP.json --out DIR [--jobs N]", "--out DIR", "--jobs N", "--threads T",
                 "--set key.path=value"}},
  };
  for (const auto& [command, texts] : commands) {
    for (const char* flag : {" --help", " -h"}) {
      const Result out = stdout_of(command + flag), err = stderr_of(command + flag);
      EXPECT_EQ(out.status, 0) << command << flag;
      EXPECT_EQ(err.output, "") << command << flag;
      for (const std::string& t : texts) EXPECT_THAT(out.output, HasSubstr(t)) << command << flag;
    }
    EXPECT_EQ(stdout_of("help " + command).output, stdout_of(command + " --help").output) << command;
  }
  EXPECT_THAT(stdout_of("run --help").output, Not(HasSubstr("--jobs")));  // the command's own options only
  // --help wins over the rest of the line: nothing runs, nothing is written.
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  EXPECT_EQ(run("run " + (d / "s.json").string() + " --out " + (d / "out").string() + " --help").status, 0);
  EXPECT_FALSE(fs::exists(d / "out"));
  EXPECT_EQ(stdout_of("help version").status, 0);
  const Result r = run("help frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("unknown command 'frobnicate'"));
  fs::remove_all(d);
}

// A negative --progress-every is refused before any work, naming the option.
TEST(RatchetCli, ANegativeProgressIntervalIsRefused) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  const Result r = run("run " + (d / "s.json").string() + " --out " + (d / "out").string() + " --progress-every -1");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--progress-every"));
  EXPECT_FALSE(fs::exists(d / "out"));
  fs::remove_all(d);
}

// The version names what built the binary, line by line, for scripts that check a
// binary against its sources (scripts/campaign_lib/engine.py).
TEST(RatchetCli, VersionFlagsAndCommand) {
  const std::string expected = std::string("ratchet ") + RATCHET_VERSION + " (" + RATCHET_BUILD_TYPE + ")\n" +
                               "commit: " + ratchet::engine_commit() + "\nsource hash: " +
                               ratchet::engine_source_hash() + "\ncompiler: " + ratchet::engine_compiler() + "\n";
  EXPECT_TRUE(std::regex_match(ratchet::engine_source_hash(), std::regex("[0-9a-f]{16}")));
  for (const char* args : {"--version", "-V", "version"}) {
    const Result r = stdout_of(args);
    EXPECT_EQ(r.status, 0) << args;
    EXPECT_EQ(r.output, expected) << args;
  }
}

// A one-run sweep of the thermal scene: valid, so that only --jobs or --out can stop it.
std::string write_sweep(const fs::path& d) {
  write(d / "sw.json", std::string(R"({"scene": )") + kThermalScene + R"(, "realizations": 1})");
  return (d / "sw.json").string();
}

TEST(RatchetCli, JobsMustBeAWholeNumberOfAtLeastOne) {
  const fs::path d = scratch();
  const std::string sweep = write_sweep(d), out = (d / "o").string();
  for (const char* jobs : {"2x", "0", "-1", "1.5", "''", "99999999999"}) {
    const Result r = run("sweep " + sweep + " --out " + out + " --jobs " + jobs);
    EXPECT_EQ(r.status, 2) << jobs << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("ratchet: --jobs: expected a whole number >= 1 (runs at a time), got '")) << jobs;
    EXPECT_FALSE(fs::exists(out)) << jobs;  // refused before any work
  }
  EXPECT_THAT(run("sweep " + sweep + " --out " + out + " --jobs=2x").output, HasSubstr("got '2x'"));
  EXPECT_THAT(run("sweep " + sweep + " --out " + out + " --jobs").output, HasSubstr("ratchet: --jobs needs a value"));
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(d);
}

TEST(RatchetCli, ThreadsPerRunMustBeAWholeNumberOfAtLeastOne) {
  const fs::path d = scratch();
  const std::string sweep = write_sweep(d), out = (d / "o").string();
  for (const char* threads : {"2x", "0", "-1", "1.5"}) {
    const Result r = run("sweep " + sweep + " --out " + out + " --threads " + threads);
    EXPECT_EQ(r.status, 2) << threads << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("ratchet: --threads: expected a whole number >= 1 (threads per run), got '"))
        << threads;
    EXPECT_FALSE(fs::exists(out)) << threads;  // refused before any work
  }
  fs::remove_all(d);
}

// A sweep's bad list of points stops it with status 2 before any work, naming the
// sweep file and the field (docs/sweeps.md, "Errors come before any work").
TEST(RatchetCli, BadSweepPointsAreRefusedNamingFileAndField) {
  const fs::path d = scratch();
  const std::string out = (d / "o").string(), sweep = (d / "pts.json").string();
  write(sweep, std::string(R"({"scene": )") + kThermalScene +
                   R"(, "points": [{"thermal.alpha_c": 1e-3}, {"thermal.alpha_p": 1e-4}]})");
  Result r = run("sweep " + sweep + " --out " + out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: " + sweep +
                                  ": field 'points[1]': expected the fields of points[0] (thermal.alpha_c), got "
                                  "thermal.alpha_p"));
  write(sweep, std::string(R"({"scene": )") + kThermalScene + R"(, "points": {"thermal.alpha_c": 1e-3}})");
  r = run("sweep " + sweep + " --out " + out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(sweep + ": field 'points': expected a non-empty list of points"));
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(d);
}

// A typo in a --set names the --set, not the scene file; a typo in the file names the file.
TEST(RatchetCli, SetErrorsNameTheOptionAndSuggestTheField) {
  const fs::path d = scratch();
  const std::string scene = (d / "s.json").string();
  write(scene, kScene);
  Result r = run("run " + scene + " --out " + (d / "out").string() + " --set solver.tolerence=1e-6");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: --set solver.tolerence=1e-6 (command-line option, applied to " +
                                  scene + "): field 'solver.tolerence': unknown field, did you mean "
                                          "'solver.tolerance'?"));
  EXPECT_THAT(r.output, Not(HasSubstr(scene + ": field")));
  EXPECT_FALSE(fs::exists(d / "out"));
  std::string typo = kScene;
  typo.replace(typo.find("\"time\""), 6, "\"solver\": {\"tolerence\": 1e-6}, \"time\"");
  write(d / "typo.json", typo);
  r = run("run " + (d / "typo.json").string() + " --explain --set solver.p_gap=0.5");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: " + (d / "typo.json").string() +
                                  ": field 'solver.tolerence': unknown field, did you mean 'solver.tolerance'?"));
  EXPECT_THAT(r.output, Not(HasSubstr("--set")));
  fs::remove_all(d);
}

// --out that cannot be the output is refused at once (exit 2), not after the work.
TEST(RatchetCli, OutThatIsAFileIsRefusedBeforeAnyWork) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  write(d / "t.json", kThermalScene);
  write(d / "afile", "keep");
  const std::string afile = (d / "afile").string(), sweep = write_sweep(d);
  Result r = run("run " + (d / "s.json").string() + " --out " + afile);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: --out " + afile +
                                  ": expected a folder, or a path where one can be created, but " + afile +
                                  " is a file"));
  r = run("run " + (d / "s.json").string() + " --out " + afile + "/sub");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--out " + afile + "/sub: expected a folder, or a path where one can be created, "
                                  "but " + afile + " is a file"));
  r = run("sweep " + sweep + " --out " + afile);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: --out " + afile + ": expected a folder"));
  EXPECT_THAT(r.output, Not(HasSubstr("ratchet sweep:")));  // no sweep started
  r = run("pack " + (d / "t.json").string() + " --out " + afile + "/p.state");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("ratchet: error: --out " + afile + "/p.state: expected a file in a folder that "
                                  "exists or can be created, but " + afile + " is a file"));
  r = run("pack " + (d / "t.json").string() + " --out " + d.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--out " + d.string() + ": expected a file (the packing), but it names a folder"));
  EXPECT_EQ(slurp(afile), "keep");
  // With --explain, --out is ignored.
  EXPECT_EQ(run("run --explain " + (d / "s.json").string() + " --out " + afile).status, 0);
  // A folder that does not exist yet, several levels deep, is fine.
  EXPECT_EQ(run("run " + (d / "s.json").string() + " --quiet --out " + (d / "new" / "deep").string()).status, 0);
  EXPECT_TRUE(fs::exists(d / "new" / "deep" / "run.json"));
  fs::remove_all(d);
}

// Generated spheres in a box region, a listed sphere and a listed box.
const char* kBodiesScene = R"({
  "name": "cli_bodies", "seed": 4, "time": {"dt": 0.01, "duration": 0.02},
  "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
  "particles": {
    "generate": {"count": 6, "shape": "sphere", "region": {"min": [0, 0, 0], "max": [8, 8, 8]}},
    "bodies": [{"shape": "sphere", "radius": 0.5, "position": [20, 0, 1]},
               {"shape": "box", "half_extents": [0.5, 0.5, 1], "position": [23, 0, 1]}]}
})";

// step-0 rows of bodies.csv: id -> (x, y, z, qw, qx, qy, qz), as read back from the text.
std::vector<std::vector<double>> first_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header: step,t,id,x,y,z,qw,qx,qy,qz,...
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line) && line.rfind("0,", 0) == 0) {
    std::stringstream ss(line);
    std::string cell;
    std::vector<double> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(std::stod(cell));
    rows.emplace_back(cells.begin() + 3, cells.begin() + 10);
  }
  return rows;
}

TEST(RatchetCli, BodiesWritesTheBodiesTheRunStartsFrom) {
  const fs::path d = scratch();
  write(d / "s.json", kBodiesScene);
  const std::string scene = (d / "s.json").string(), file = (d / "deep" / "b.json").string();
  Result r = run("bodies " + scene + " --out " + file + " --set seed=9");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("ratchet: cli_bodies: 8 bodies, 1 shapes -> " + file));
  EXPECT_FALSE(fs::exists(file + ".partial"));
  const nlohmann::json doc = nlohmann::json::parse(slurp(file));
  EXPECT_EQ(doc.at("format"), "ratchet-bodies");
  EXPECT_EQ(doc.at("version"), 1);
  EXPECT_EQ(doc.at("seed"), 9);  // the --set applies
  ASSERT_EQ(doc.at("bodies").size(), 8u);
  EXPECT_EQ(doc["bodies"][6].at("radius"), 0.5);
  EXPECT_EQ(doc["bodies"][7].at("kind"), "polyhedron");
  EXPECT_EQ(doc["bodies"][7].at("shape"), 0);
  EXPECT_EQ(doc.at("shapes").size(), 1u);
  EXPECT_EQ(doc["shapes"][0].at("vertices").size(), 8u);
  // The same scene and --set run: its step-0 rows are the file's bodies, bit for bit,
  // and its folder holds the same document.
  r = run("run " + scene + " --out " + (d / "out").string() + " --set seed=9 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = first_rows(d / "out" / "bodies.csv");
  ASSERT_EQ(rows.size(), 8u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json& b = doc["bodies"][i];
    for (int a = 0; a < 3; ++a) EXPECT_EQ(rows[i][a], b["position"][a].get<double>()) << i;
    for (int a = 0; a < 4; ++a) EXPECT_EQ(rows[i][3 + a], b["orientation"][a].get<double>()) << i;
  }
  const nlohmann::json in_run = nlohmann::json::parse(slurp(d / "out" / "bodies_shapes.json"));
  EXPECT_EQ(in_run.at("bodies"), doc.at("bodies"));
  EXPECT_EQ(in_run.at("shapes"), doc.at("shapes"));
  EXPECT_EQ(in_run.at("scene_hash"), doc.at("scene_hash"));
  // Another seed, other generated bodies.
  ASSERT_EQ(run("bodies " + scene + " --out " + file + " --quiet").status, 0);
  EXPECT_NE(nlohmann::json::parse(slurp(file))["bodies"][0].at("position"), doc["bodies"][0].at("position"));
  fs::remove_all(d);
}

TEST(RatchetCli, BodiesRefusesBadInputBeforeWritingAnything) {
  const fs::path d = scratch();
  write(d / "s.json", kBodiesScene);
  write(d / "afile", "keep");
  const std::string scene = (d / "s.json").string(), file = (d / "b.json").string();
  Result r = run("bodies " + scene + " --out " + file + " --set particles.generate.spacing=0.1");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("field 'particles.generate.spacing'"));
  EXPECT_FALSE(fs::exists(file));
  r = run("bodies " + scene);
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--out FILE.json is required"));
  r = run("bodies " + scene + " --out " + d.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output,
              HasSubstr("--out " + d.string() + ": expected a file (the bodies file), but it names a folder"));
  r = run("bodies " + scene + " --out " + (d / "afile" / "b.json").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("expected a file in a folder that exists or can be created"));
  r = run("bodies a.json b.json --out x.json");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("more than one scene file given ('a.json', 'b.json')"));
  r = run("bodies " + scene + " --out " + file + " --explain");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("unknown option '--explain'"));
  EXPECT_FALSE(fs::exists(file));
  EXPECT_EQ(slurp(d / "afile"), "keep");
  fs::remove_all(d);
}

}  // namespace

namespace {

// --resume: what it refuses, each before any work, with exit 2.
TEST(RatchetCli, ResumeRefusesWhatItCannotContinue) {
  const fs::path d = scratch();
  write(d / "s.json", kScene);
  Result r = run("run --resume " + (d / "none").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--resume " + (d / "none").string() + ": expected the folder of a run"));
  r = run("run " + (d / "s.json").string() + " --resume " + d.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--resume continues a run as it was"));
  r = run("run --resume " + d.string() + " --set solver.tolerance=1e-3");
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--resume continues a run as it was"));
  r = run("run --resume " + d.string());  // a folder without a checkpoint
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr((d / "checkpoint.state").string() + ": no checkpoint to resume from"));
  ASSERT_EQ(run("run " + (d / "s.json").string() + " --out " + (d / "done").string() + " --quiet").status, 0);
  r = run("run --resume " + (d / "done").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("the run is already completed"));
  EXPECT_FALSE(fs::exists(d / "done" / "checkpoint.state"));  // a finished run keeps none
}

}  // namespace

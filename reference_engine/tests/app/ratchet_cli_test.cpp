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

TEST(RatchetCli, UsageErrors) {
  EXPECT_EQ(run("").status, 2);
  EXPECT_EQ(run("frobnicate").status, 2);
  EXPECT_EQ(run("run scene.json").status, 2);  // no --out
  EXPECT_EQ(run("--version").status, 0);
}

}  // namespace

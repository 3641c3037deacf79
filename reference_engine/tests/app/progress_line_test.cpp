// The progress line of `ratchet run` and `ratchet pack` (run/runner.hpp): on a terminal
// it is cut to the width and cleared to the end of the line; elsewhere (a batch job's
// log) run_world writes whole timestamped lines.
#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <regex>
#include <sstream>
#include <vector>

#include <cstdlib>
#include <optional>
#include <string>

#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"

namespace ratchet {
namespace {

// The settling line of docs/cli.md, about 98 characters: wider than an 80-column terminal.
const std::string kLong =
    "bed_quick: step 2156/7000 at most, settling (30.8%) t=8.624 T=0 contacts=104 iter=45  5s left";

TEST(ProgressLine, NotATerminalKeepsTheOldForm) {
  EXPECT_EQ(progress_line("fall: step 1/10 (10.0%)", 0), "\rfall: step 1/10 (10.0%)   ");
  EXPECT_EQ(progress_line(kLong, 0), "\r" + kLong + "   ");  // never cut
}

TEST(ProgressLine, OnATerminalClearsToTheEndOfTheLine) {
  // A shorter line after a longer one: \x1b[K removes what the longer one left.
  EXPECT_EQ(progress_line("fall: step 10/10", 80), "\rfall: step 10/10\x1b[K");
}

TEST(ProgressLine, OnATerminalIsCutToTheWidthLeavingTheLastColumnFree) {
  ASSERT_GT(kLong.size(), 80u);
  EXPECT_EQ(progress_line(kLong, 80), "\r" + kLong.substr(0, 79) + "\x1b[K");
  EXPECT_EQ(progress_line(kLong, 40), "\r" + kLong.substr(0, 39) + "\x1b[K");
  const std::string fits(79, 'x');
  EXPECT_EQ(progress_line(fits, 80), "\r" + fits + "\x1b[K");                  // 79 characters fit
  EXPECT_EQ(progress_line(fits + "y", 80), "\r" + fits + "\x1b[K");            // the 80th does not
  EXPECT_EQ(progress_line(kLong, 1), "\r" + kLong.substr(0, 1) + "\x1b[K");    // something always shows
  EXPECT_EQ(progress_line(kLong, 1000), "\r" + kLong + "\x1b[K");              // wide enough: whole
}

TEST(ProgressLine, CutsBetweenUtf8Characters) {
  const std::string name = "b\xc3\xa9t\xc3\xa9";  // "bete" with two 2-byte e-acute: 5 characters, 7 bytes
  EXPECT_EQ(progress_line(name + ": step 1", 4), "\rb\xc3\xa9t\x1b[K");         // 3 characters, 4 bytes
  EXPECT_EQ(progress_line(name + ": step 1", 5), "\rb\xc3\xa9t\xc3\xa9\x1b[K");  // never half of one
}

// Restores $COLUMNS after a test changes it.
class Columns : public ::testing::Test {
 protected:
  std::optional<std::string> saved;
  int fd = -1;  // not a terminal: TIOCGWINSZ fails on it
  void SetUp() override {
    if (const char* c = std::getenv("COLUMNS")) saved = c;
    fd = open("/dev/null", O_WRONLY);
    ASSERT_GE(fd, 0);
  }
  void TearDown() override {
    close(fd);
    if (saved) setenv("COLUMNS", saved->c_str(), 1);
    else unsetenv("COLUMNS");
  }
};

TEST_F(Columns, WithoutTheTerminalsSizeTakeColumnsThen80) {
  setenv("COLUMNS", "123", 1);
  EXPECT_EQ(terminal_columns(fd), 123);
  for (const char* bad : {"", "12x", "0", "-5", "wide"}) {
    setenv("COLUMNS", bad, 1);
    EXPECT_EQ(terminal_columns(fd), 80) << "'" << bad << "'";
  }
  unsetenv("COLUMNS");
  EXPECT_EQ(terminal_columns(fd), 80);
}

// run_world with progress on and stderr not a terminal (captured into a file), as in a
// batch job's log: whole lines, each stamped with the UTC time, the time left before
// anything else, no carriage return or escape sequence and no cut; with log_every 0 only
// the last step's line, with a tiny log_every one line per step.
World long_named_world() {
  return World(build_scene(nlohmann::json::parse(R"({
    "name": "a_scene_name_long_enough_to_pass_eighty_columns_with_the_rest_of_the_line",
    "time": {"dt": 0.01, "duration": 0.05},
    "container": {"type": "planes", "planes": [{"normal": [0, 0, 1], "point": [0, 0, 0]}]},
    "particles": {"bodies": [{"shape": "sphere", "radius": 0.5, "position": [0, 0, 2]}]}
  })"),
                           "long.json"));
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(ProgressLine, RunWorldOffATerminalWritesStampedLines) {
  const std::regex line(
      R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ a_scene_name_long_enough_to_pass_eighty_columns_with_the_rest_of_the_line: )"
      R"((\d+s|\d+m\d\ds|\d+h\d\dm) left, step (\d)/5 \((\d+\.\d)%\) t=[0-9.e-]+ T=0 contacts=\d+ iter=\d+$)");
  for (const double every : {0.0, 1e-9}) {
    World world = long_named_world();
    RunOptions opt;
    opt.progress = true;
    opt.log_every = every;
    ::testing::internal::CaptureStderr();
    run_world(world, opt);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err.find('\r'), std::string::npos) << err;
    EXPECT_EQ(err.find('\x1b'), std::string::npos) << err;
    const std::vector<std::string> lines = lines_of(err);
    ASSERT_EQ(lines.size(), every > 0.0 ? 5u : 1u) << err;
    for (std::size_t k = 0; k < lines.size(); ++k) {
      std::smatch m;
      ASSERT_TRUE(std::regex_match(lines[k], m, line)) << lines[k];
      EXPECT_EQ(std::stoi(m[2].str()), static_cast<int>(k + 6 - lines.size()));  // the last line is step 5
    }
  }
}

TEST(ProgressLine, UtcStampIsIso8601) {
  EXPECT_TRUE(std::regex_match(utc_stamp(), std::regex(R"(^20\d\d-[01]\d-[0-3]\dT[0-2]\d:[0-5]\d:[0-6]\dZ$)")));
}

}  // namespace
}  // namespace ratchet

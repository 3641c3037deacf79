#include "ratchet/io/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace ratchet {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("ratchet_atomic_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(AtomicFile, NothingAppearsUnderTheFinalNameUntilCommit) {
  const fs::path d = temp_dir();
  const std::string path = (d / "out.csv").string();
  {
    AtomicFile f(path);
    f.stream() << "a,b\n";
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(fs::exists(path + ".partial"));
    f.commit();
  }
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "a,b\n");
  EXPECT_FALSE(fs::exists(path + ".partial"));
  fs::remove_all(d);
}

TEST(AtomicFile, AnAbandonedFileLeavesNothing) {
  const fs::path d = temp_dir();
  const std::string path = (d / "out.csv").string();
  { AtomicFile f(path); f.stream() << "partial"; }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  fs::remove_all(d);
}

TEST(AtomicFile, UnwritableFolderThrows) {
  EXPECT_THROW(AtomicFile("/nonexistent-dir/x.csv"), std::runtime_error);
}

// A resumed run (run/checkpoint.hpp): the .partial is cut back to the checkpoint's
// length, appended to, and committed as one file; the bytes after the cut are gone.
TEST(AtomicFile, ResumeCutsBackToTheCheckpointAndAppends) {
  const fs::path d = temp_dir();
  const std::string path = (d / "ts.csv").string();
  std::uintmax_t at = 0;
  {
    AtomicFile f(path);
    f.stream() << "h\n1\n";
    at = f.flush_size();
    f.stream() << "2 written after the checkpoint\n";
    f.keep();  // as a stopped run leaves it
  }
  EXPECT_EQ(at, 4u);
  ASSERT_TRUE(fs::exists(path + ".partial"));  // kept, not removed
  {
    AtomicFile f(path, at);
    EXPECT_EQ(f.flush_size(), 4u);
    f.stream() << "2\n";
    f.commit();
  }
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "h\n1\n2\n");
}

TEST(AtomicFile, ResumeRefusesAMissingOrShorterFileNamingIt) {
  const fs::path d = temp_dir();
  const std::string path = (d / "ts.csv").string();
  try {
    AtomicFile f(path, 0);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ".partial: cannot resume"), std::string::npos) << e.what();
  }
  std::ofstream(path + ".partial") << "abc";
  try {
    AtomicFile f(path, 4);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("3 bytes, the checkpoint expects at least 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ratchet

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

}  // namespace
}  // namespace ratchet

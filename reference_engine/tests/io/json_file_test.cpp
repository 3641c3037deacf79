#include "ratchet/io/json_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/test_files.hpp"

namespace ratchet {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

std::string error_of(const std::string& path) {
  try {
    read_json_file(path, "scene file");
  } catch (const JsonFileError& e) {
    return e.what();
  }
  return "";
}

TEST(JsonFile, ReadsCommentedJson) {
  const fs::path d = test::fresh_dir("json_file");
  std::ofstream(d / "a.json") << "{\"x\": 1 // why\n}";
  EXPECT_EQ(read_json_file((d / "a.json").string(), "scene file").at("x"), 1);
}

TEST(JsonFile, SaysWhyAFileCannotBeOpened) {
  const fs::path d = test::fresh_dir("json_file");
  EXPECT_EQ(error_of((d / "absent.json").string()), (d / "absent.json").string() + ": cannot open the scene file (no such file)");
  EXPECT_EQ(error_of(d.string()), d.string() + ": cannot open the scene file (a folder, not a file)");
}

TEST(JsonFile, SyntaxErrorsGiveLineAndColumnWithoutTheLibrarysTag) {
  const fs::path d = test::fresh_dir("json_file");
  std::ofstream(d / "b.json") << "{\n  \"x\": 1,\n}";
  const std::string msg = error_of((d / "b.json").string());
  EXPECT_THAT(msg, HasSubstr("b.json: not valid JSON: parse error at line 3, column 1"));
  EXPECT_THAT(msg, Not(HasSubstr("[json.exception")));
}

TEST(JsonFile, ANumberBeyondADoubleIsAnErrorOfTheFile) {
  const fs::path d = test::fresh_dir("json_file");
  std::ofstream(d / "c.json") << "{\"x\": 1e999}";
  EXPECT_THAT(error_of((d / "c.json").string()), HasSubstr("c.json: not valid JSON: number overflow"));
}

}  // namespace
}  // namespace ratchet

#include "support/check_record.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ratchet::validation {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Each test gets its own checks folder in RATCHET_CHECKS_DIR, removed afterwards.
class CheckRecordTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::path(::testing::TempDir()) / "check_record_test.XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << "cannot create a temporary folder";
    dir_ = pattern;
    ASSERT_EQ(::setenv("RATCHET_CHECKS_DIR", dir_.c_str(), 1), 0);
  }
  void TearDown() override {
    ::unsetenv("RATCHET_CHECKS_DIR");
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  std::vector<fs::path> files() const {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir_)) found.push_back(entry.path());
    return found;
  }

  // The lines of the one file this process wrote, parsed.
  std::vector<json> lines() const {
    const auto found = files();
    EXPECT_EQ(found.size(), 1u);
    if (found.size() != 1) return {};
    const std::string suffix = "-" + std::to_string(::getpid()) + ".jsonl";
    const std::string name = found[0].filename().string();
    EXPECT_GT(name.size(), suffix.size());
    EXPECT_EQ(name.substr(name.size() - suffix.size()), suffix) << name;
    std::ifstream in(found[0]);
    std::vector<json> parsed;
    for (std::string line; std::getline(in, line);) parsed.push_back(json::parse(line));
    return parsed;
  }

  fs::path dir_;
};

TEST_F(CheckRecordTest, RecordsPassingAndFailingChecks) {
  const double measured = 0.1 + 0.2;  // 0.30000000000000004: needs all 17 digits
  EXPECT_TRUE(check_near("free_fall", "z(t=1)", measured, 0.3, 1e-12, "exact integrator"));
  EXPECT_FALSE(check_rel("wall_pressure", "P_max", 1.2, 1.0, 0.05, "coarse bed"));
  EXPECT_TRUE(check_le("energy", "kinetic energy", 1e-9, 1e-6, "bed at rest"));
  EXPECT_FALSE(record("manual", "custom", 2.5, "3 +- 0.1", "abs 0.1", false, "why"));

  const auto parsed = lines();
  ASSERT_EQ(parsed.size(), 4u);

  const std::set<std::string> fields = {"case",      "check",  "measured", "expected",
                                        "tolerance", "reason", "passed"};
  for (const auto& line : parsed) {
    std::set<std::string> keys;
    for (const auto& item : line.items()) keys.insert(item.key());
    EXPECT_EQ(keys, fields) << line.dump();
  }

  EXPECT_EQ(parsed[0]["case"], "free_fall");
  EXPECT_EQ(parsed[0]["check"], "z(t=1)");
  EXPECT_EQ(parsed[0]["measured"].get<double>(), measured);  // exact round trip
  EXPECT_EQ(parsed[0]["expected"], "0.3");
  EXPECT_EQ(parsed[0]["tolerance"], "abs 1e-12");
  EXPECT_EQ(parsed[0]["reason"], "exact integrator");
  EXPECT_EQ(parsed[0]["passed"], true);

  EXPECT_EQ(parsed[1]["case"], "wall_pressure");
  EXPECT_EQ(parsed[1]["measured"].get<double>(), 1.2);
  EXPECT_EQ(parsed[1]["expected"], "1");
  EXPECT_EQ(parsed[1]["tolerance"], "rel 0.05");
  EXPECT_EQ(parsed[1]["passed"], false);

  EXPECT_EQ(parsed[2]["expected"], "<= 1e-06");
  EXPECT_EQ(parsed[2]["passed"], true);

  EXPECT_EQ(parsed[3]["expected"], "3 +- 0.1");
  EXPECT_EQ(parsed[3]["tolerance"], "abs 0.1");
  EXPECT_EQ(parsed[3]["reason"], "why");
  EXPECT_EQ(parsed[3]["passed"], false);
}

TEST_F(CheckRecordTest, NonFiniteMeasuredIsNullAndFails) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(record("c", "nan passed", nan, "1", "abs 1", true));
  EXPECT_FALSE(check_le("c", "nan <= 1", nan, 1.0, "r"));
  EXPECT_FALSE(check_le("c", "-inf <= 1", -inf, 1.0, "r"));
  EXPECT_FALSE(check_near("c", "inf near", inf, inf, 1.0, "r"));

  const auto parsed = lines();
  ASSERT_EQ(parsed.size(), 4u);
  for (const auto& line : parsed) {
    EXPECT_TRUE(line["measured"].is_null()) << line.dump();
    EXPECT_EQ(line["passed"], false) << line.dump();
  }
  EXPECT_EQ(parsed[3]["expected"], "inf");
}

TEST_F(CheckRecordTest, RoundTripsExtremeValues) {
  const std::vector<double> values = {1.0 / 3.0, -2.0 / 3.0, 1e-300, 4.9e-324, 1.7976931348623157e308,
                                      123456789.12345678, 0.0, -0.0};
  for (double v : values) record("c", "v", v, "", "", true);
  const auto parsed = lines();
  ASSERT_EQ(parsed.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_EQ(parsed[i]["measured"].get<double>(), values[i]) << parsed[i].dump();
}

TEST_F(CheckRecordTest, ToleranceBoundariesAreInclusive) {
  EXPECT_TRUE(check_near("c", "at abs bound", 1.5, 1.0, 0.5, "r"));
  EXPECT_TRUE(check_rel("c", "at rel bound", 1.5, 1.0, 0.5, "r"));
  EXPECT_TRUE(check_le("c", "at bound", 2.0, 2.0, "r"));
  EXPECT_FALSE(check_le("c", "above bound", std::nextafter(2.0, 3.0), 2.0, "r"));
  EXPECT_TRUE(check_rel("c", "zero expected, exact", 0.0, 0.0, 0.1, "r"));
  EXPECT_FALSE(check_rel("c", "zero expected, off", 1e-300, 0.0, 0.1, "r"));
}

TEST_F(CheckRecordTest, WritesNothingWithoutTheVariable) {
  ::unsetenv("RATCHET_CHECKS_DIR");
  EXPECT_TRUE(check_near("c", "x", 1.0, 1.0, 0.0, "r"));
  EXPECT_FALSE(check_near("c", "y", 2.0, 1.0, 0.0, "r"));
  EXPECT_TRUE(files().empty());
}

TEST_F(CheckRecordTest, CreatesAMissingFolder) {
  const fs::path nested = dir_ / "a" / "b";
  ASSERT_EQ(::setenv("RATCHET_CHECKS_DIR", nested.c_str(), 1), 0);
  EXPECT_TRUE(check_le("c", "x", 0.0, 1.0, "r"));
  ASSERT_TRUE(fs::is_directory(nested));
  EXPECT_EQ(std::distance(fs::directory_iterator(nested), fs::directory_iterator()), 1);
}

TEST_F(CheckRecordTest, UnwritableFolderThrows) {
  const fs::path blocker = dir_ / "not_a_folder";
  std::ofstream(blocker) << "x";
  ASSERT_EQ(::setenv("RATCHET_CHECKS_DIR", blocker.c_str(), 1), 0);
  EXPECT_THROW(check_le("c", "x", 0.0, 1.0, "r"), std::runtime_error);
}

TEST(FormatNumber, ShortestExactText) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(1e-6), "1e-06");
  EXPECT_EQ(format_number(2.0), "2");
  EXPECT_EQ(format_number(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(std::strtod(format_number(1.0 / 3.0).c_str(), nullptr), 1.0 / 3.0);
}

}  // namespace
}  // namespace ratchet::validation

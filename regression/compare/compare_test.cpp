// Tests of the C++ comparison rule (compare.hpp) against the shared test vectors
// regression/compare_vectors.json, which the Python implementation's pytest
// (scripts/tests/test_regression_compare.py) checks too: the same expected figures for
// both, so the two implementations are one rule. Plus manifest errors and CSV reading.
#include "compare/compare.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace rr = ratchet::regression;
namespace fs = std::filesystem;

namespace {

nlohmann::json load_vectors() {
  std::ifstream in(RATCHET_COMPARE_VECTORS);
  EXPECT_TRUE(in.good()) << "cannot open " << RATCHET_COMPARE_VECTORS;
  nlohmann::json v;
  in >> v;
  return v;
}

const nlohmann::json& vectors() {
  static const nlohmann::json v = load_vectors();
  return v;
}

::testing::AssertionResult close(double got, const nlohmann::json& expected_json, const char* what) {
  const double expected = rr::from_json_number(expected_json);
  const double rel = vectors().at("rel_tolerance").get<double>();
  bool ok;
  if (std::isnan(expected)) ok = std::isnan(got);
  else if (std::isinf(expected)) ok = got == expected;
  else ok = std::fabs(got - expected) <= rel * std::max(std::fabs(expected), 1e-300);
  if (ok) return ::testing::AssertionSuccess();
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s: got %.17g, expected %.17g", what, got, expected);
  return ::testing::AssertionFailure() << buf;
}

std::vector<double> numbers(const nlohmann::json& xs) {
  std::vector<double> out;
  for (const auto& x : xs) out.push_back(rr::from_json_number(x));
  return out;
}

void check_expect(const rr::ColumnResult& r, const nlohmann::json& v) {
  SCOPED_TRACE(v.at("name").get<std::string>() + ": " + v.at("note").get<std::string>());
  const auto& e = v.at("expect");
  EXPECT_EQ(r.passed, e.at("passed").get<bool>());
  EXPECT_EQ(r.n, e.at("n").get<std::size_t>());
  EXPECT_EQ(r.failures, e.at("failures").get<std::size_t>());
  EXPECT_EQ(r.worst_row, e.at("worst_row").get<long>());
  EXPECT_TRUE(close(r.mean, e.at("mean"), "mean"));
  EXPECT_TRUE(close(r.std, e.at("std"), "std"));
  EXPECT_TRUE(close(r.max, e.at("max"), "max"));
  EXPECT_TRUE(close(r.worst_new, e.at("worst_new"), "worst_new"));
  EXPECT_TRUE(close(r.worst_golden, e.at("worst_golden"), "worst_golden"));
  if (e.contains("worst_se")) {
    EXPECT_TRUE(close(r.worst_se, e.at("worst_se"), "worst_se"));
  }
}

}  // namespace

TEST(CompareVectors, Deterministic) {
  ASSERT_FALSE(vectors().at("deterministic").empty());
  for (const auto& v : vectors().at("deterministic")) {
    const auto r = rr::compare_deterministic("x", numbers(v.at("new")), numbers(v.at("golden")),
                                             v.at("tol").get<double>(), v.at("floor").get<double>(),
                                             v.at("scale").get<double>());
    check_expect(r, v);
  }
}

TEST(CompareVectors, Ensemble) {
  ASSERT_FALSE(vectors().at("ensemble").empty());
  for (const auto& v : vectors().at("ensemble")) {
    std::vector<std::vector<double>> a, b;
    for (const auto& real : v.at("new")) a.push_back(numbers(real));
    for (const auto& real : v.at("golden")) b.push_back(numbers(real));
    const auto r = rr::compare_ensemble("x", a, b, v.at("tol").get<double>(), v.at("floor").get<double>(),
                                        v.at("scale").get<double>());
    check_expect(r, v);
  }
}

TEST(CompareVectors, Keys) {
  EXPECT_EQ(vectors().at("key_tol").get<double>(), rr::kKeyTol);
  EXPECT_EQ(vectors().at("key_floor").get<double>(), rr::kKeyFloor);
  for (const auto& v : vectors().at("keys")) {
    SCOPED_TRACE(v.at("name").get<std::string>());
    std::vector<std::vector<double>> a, b;
    for (double x : numbers(v.at("new"))) a.push_back({x});
    for (double x : numbers(v.at("golden"))) b.push_back({x});
    EXPECT_EQ(rr::first_key_mismatch(a, b), v.at("expect_first_mismatch").get<long>());
  }
}

TEST(CompareRule, ValueErrorAndBound) {
  EXPECT_EQ(rr::value_error(1.5, 1.0, 1e-9), 0.5);
  EXPECT_EQ(rr::value_error(std::nan(""), std::nan(""), 1.0), 0.0);
  EXPECT_TRUE(std::isinf(rr::value_error(HUGE_VAL, 1.0, 1.0)));
  EXPECT_TRUE(rr::within(0.5, 0.5, 1.0));
  EXPECT_FALSE(rr::within(0.5, 0.5, 0.99));
  EXPECT_FALSE(rr::within(1e-300, 1.0, 0.0));  // scale 0: every nonzero residual fails
}

TEST(CompareRule, TolScaleSources) {
  EXPECT_EQ(rr::tol_scale_from(nullptr, nullptr), 1.0);
  EXPECT_EQ(rr::tol_scale_from(nullptr, "0"), 0.0);
  EXPECT_EQ(rr::tol_scale_from("2.5", "0"), 2.5);  // the option wins over the environment
  for (const char* bad : {"-1", "abc", "nan", "inf", "1x"}) EXPECT_THROW(rr::tol_scale_from(bad, nullptr), std::invalid_argument) << bad;
  try {
    rr::tol_scale_from(nullptr, "x");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("RATCHET_TOL_SCALE"), std::string::npos);
  }
}

namespace {

nlohmann::ordered_json good_manifest() {
  return nlohmann::ordered_json::parse(R"({"format": 1, "case": "demo", "description": "d", "kind": "deterministic",
    "scene": "s.json", "realizations": [{"seed": 1, "folder": "seed-1", "scene_hash": null}],
    "tables": [{"file": "timeseries.csv", "key": "t",
                "columns": {"x": {"tol": 1e-9, "floor": 1e-6, "reason": "why"}}}]})");
}

std::string manifest_error(const nlohmann::ordered_json& m) {
  try {
    rr::parse_manifest("golden/demo/manifest.json", m);
  } catch (const rr::ManifestError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CompareManifest, ErrorsNameFileAndField) {
  EXPECT_EQ(manifest_error(good_manifest()), "");
  struct Case {
    const char* pointer;
    nlohmann::ordered_json value;
    const char* field;
  };
  const Case cases[] = {
      {"/kind", "fuzzy", "'kind'"},
      {"/format", 2, "'format'"},
      {"/tables/0/columns/x/floor", 0, "'tables[0].columns.x.floor'"},
      {"/tables/0/columns/x/tol", -1, "'tables[0].columns.x.tol'"},
      {"/tables/0/columns/x/reason", "", "'tables[0].columns.x.reason'"},
      {"/tables/0/file", "timeseries.txt", "'tables[0].file'"},
      {"/tables/0/key", nlohmann::ordered_json::array(), "'tables[0].key'"},
      {"/realizations/0/folder", "a/b", "'realizations[0].folder'"},
  };
  for (const auto& c : cases) {
    auto m = good_manifest();
    m[nlohmann::ordered_json::json_pointer(c.pointer)] = c.value;
    const std::string msg = manifest_error(m);
    EXPECT_NE(msg.find("golden/demo/manifest.json"), std::string::npos) << c.pointer << ": " << msg;
    EXPECT_NE(msg.find(c.field), std::string::npos) << c.pointer << ": " << msg;
  }
  auto m = good_manifest();
  m["kind"] = "ensemble";  // columns still say "tol"
  const std::string msg = manifest_error(m);
  EXPECT_NE(msg.find("'tables[0].columns.x.tol'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'tol' is for deterministic cases"), std::string::npos) << msg;
}

TEST(CompareCase, StructuralProblemsAndAlignedComparison) {
  const fs::path dir = fs::temp_directory_path() / ("compare_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "golden" / "seed-1");
  fs::create_directories(dir / "new" / "seed-1");
  auto write = [](const fs::path& p, const std::string& text) { std::ofstream(p) << text; };
  const auto m = rr::parse_manifest((dir / "golden" / "manifest.json").string(), good_manifest());
  const std::string g = (dir / "golden").string(), n = (dir / "new").string();

  write(dir / "new" / "seed-1" / "timeseries.csv", "t,x\n0,1\n");
  auto r = rr::compare_case(m, g, n, 1.0);  // golden file missing: a failure, never a regeneration
  ASSERT_FALSE(r.passed());
  EXPECT_NE(r.problems.at(0).find("--update demo"), std::string::npos) << r.problems.at(0);
  EXPECT_FALSE(fs::exists(dir / "golden" / "seed-1" / "timeseries.csv"));

  write(dir / "golden" / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.5,2\n");
  write(dir / "new" / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.25,2\n");
  r = rr::compare_case(m, g, n, 1.0);
  ASSERT_FALSE(r.passed());
  EXPECT_NE(r.problems.at(0).find("key t differs at row 2"), std::string::npos) << r.problems.at(0);

  write(dir / "new" / "seed-1" / "timeseries.csv", "t,y\n0,1\n0.5,2\n");
  r = rr::compare_case(m, g, n, 1.0);
  ASSERT_FALSE(r.passed());
  EXPECT_NE(r.problems.at(0).find("no column 'x'"), std::string::npos) << r.problems.at(0);

  write(dir / "new" / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.5,2.0000000001\n");
  r = rr::compare_case(m, g, n, 1.0);
  EXPECT_TRUE(r.passed());
  ASSERT_EQ(r.columns.size(), 1u);
  EXPECT_NEAR(r.columns[0].max, 5e-11, 1e-15);
  EXPECT_EQ(r.columns[0].worst_key, std::vector<double>{0.5});
  r = rr::compare_case(m, g, n, 0.0);  // the residual mode: the nonzero residual fails
  EXPECT_FALSE(r.passed());
  EXPECT_NE(rr::format_report(r, m).find("case demo: FAIL"), std::string::npos);
  fs::remove_all(dir);
}

TEST(CompareTable, CellsAndErrors) {
  double v;
  ASSERT_TRUE(rr::parse_cell("0.30000000000000004", v));
  EXPECT_EQ(v, 0.30000000000000004);
  ASSERT_TRUE(rr::parse_cell("", v));
  EXPECT_TRUE(std::isnan(v));
  ASSERT_TRUE(rr::parse_cell("-inf", v));
  EXPECT_TRUE(std::isinf(v) && v < 0);
  EXPECT_FALSE(rr::parse_cell("completed", v));
  EXPECT_FALSE(rr::parse_cell("1.5x", v));
  EXPECT_THROW(rr::read_table("/nonexistent/timeseries.csv"), rr::TableError);
}

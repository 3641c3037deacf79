// The points of a sweep file (run/sweep_points.hpp): a grid's combinations in odometer
// order, a list of points in its order, one empty point without either, and every
// malformed grid or list refused naming the file and the field.
#include "ratchet/run/sweep_points.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "ratchet/scene/scene.hpp"

namespace ratchet {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

TEST(SweepPoints, GridIsEveryCombinationLastKeyFastest) {
  std::vector<std::string> keys;
  const auto points = sweep_points({{"grid", {{"b", {1, 2}}, {"a", {"x", "y", "z"}}}}}, "s.json", keys);
  EXPECT_EQ(keys, (std::vector<std::string>{"a", "b"}));  // sorted
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0], (std::vector<json>{"x", 1}));
  EXPECT_EQ(points[1], (std::vector<json>{"x", 2}));
  EXPECT_EQ(points[2], (std::vector<json>{"y", 1}));
  EXPECT_EQ(points[5], (std::vector<json>{"z", 2}));
}

TEST(SweepPoints, ListedPointsKeepTheirOrder) {
  std::vector<std::string> keys = {"stale"};
  const json sweep = {{"points", {{{"thermal.alpha_c", 1e-3}, {"container.opening_angle_deg", 6}},
                                  {{"container.opening_angle_deg", 0}, {"thermal.alpha_c", 1e-4}},
                                  {{"container.opening_angle_deg", 2}, {"thermal.alpha_c", 1e-3}}}}};
  const auto points = sweep_points(sweep, "s.json", keys);
  EXPECT_EQ(keys, (std::vector<std::string>{"container.opening_angle_deg", "thermal.alpha_c"}));
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[0], (std::vector<json>{6, 1e-3}));  // the file's order, not sorted
  EXPECT_EQ(points[1], (std::vector<json>{0, 1e-4}));
  EXPECT_EQ(points[2], (std::vector<json>{2, 1e-3}));
}

TEST(SweepPoints, NeitherIsOnePointWithNoKeys) {
  std::vector<std::string> keys = {"stale"};
  const auto points = sweep_points({{"scene", "x.json"}}, "s.json", keys);
  EXPECT_TRUE(keys.empty());
  ASSERT_EQ(points.size(), 1u);
  EXPECT_TRUE(points[0].empty());
}

std::string error_of(const json& sweep) {
  std::vector<std::string> keys;
  try {
    sweep_points(sweep, "dir/s.json", keys);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SweepPoints, MalformedOnesNameTheFileAndTheField) {
  EXPECT_THAT(error_of({{"grid", {{"a", {1}}}}, {"points", {{{"a", 1}}}}}),
              HasSubstr("dir/s.json: field 'points': expected either a grid or a list of points, not both"));
  EXPECT_THAT(error_of({{"points", json::array()}}),
              HasSubstr("dir/s.json: field 'points': expected a non-empty list of points"));
  EXPECT_THAT(error_of({{"points", {{"a", 1}}}}), HasSubstr("dir/s.json: field 'points'"));  // an object, not a list
  EXPECT_THAT(error_of({{"points", {{{"a", 1}}, 5}}}), HasSubstr("dir/s.json: field 'points[1]': expected a non-empty object"));
  EXPECT_THAT(error_of({{"points", {{{"a", 1}}, json::object()}}}), HasSubstr("field 'points[1]'"));
  EXPECT_THAT(error_of({{"points", {{{"a", 1}, {"b", 2}}, {{"a", 3}}}}}),
              HasSubstr("dir/s.json: field 'points[1]': expected the fields of points[0] (a, b), got a"));
  EXPECT_THAT(error_of({{"points", {{{"a", 1}}, {{"a", 2}}, {{"a", 1}}}}}),
              HasSubstr("dir/s.json: field 'points[2]': expected a point not listed before (it is points[0] again)"));
  EXPECT_THAT(error_of({{"grid", {{"a", 1}}}}), HasSubstr("dir/s.json: field 'grid.a': expected a non-empty list"));
  EXPECT_THAT(error_of({{"grid", {1, 2}}}), HasSubstr("dir/s.json: field 'grid': expected an object"));
}

}  // namespace
}  // namespace ratchet

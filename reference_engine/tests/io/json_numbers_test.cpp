#include "ratchet/io/json_numbers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "../support/test_files.hpp"

namespace ratchet {
namespace {

using test::bits;

// Through a dump and a parse, as in a checkpoint file: every bit comes back.
double round_trip(double x) { return number_from_json(nlohmann::json::parse(json_number(x).dump())); }

TEST(JsonNumbers, EveryDoubleComesBackBitForBit) {
  for (double x : {0.0, -0.0, 0.1, 1.0 / 3.0, 9.440000000000002, 1e-310 /* subnormal */, -2.2250738585072014e-308,
                   std::numeric_limits<double>::max(), std::nextafter(1.0, 2.0), HUGE_VAL, -HUGE_VAL})
    EXPECT_EQ(bits(round_trip(x)), bits(x)) << x;
  EXPECT_TRUE(std::isnan(round_trip(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_EQ(json_number(-HUGE_VAL), "-inf");  // not null, which would not say which
}

TEST(JsonNumbers, VectorsAndPointsRoundTrip) {
  const std::vector<double> xs{1.5, NAN, -HUGE_VAL};
  const std::vector<double> back = numbers_from_json(nlohmann::json::parse(json_numbers(xs).dump()));
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0], 1.5);
  EXPECT_TRUE(std::isnan(back[1]));
  EXPECT_EQ(back[2], -HUGE_VAL);
  const std::vector<Vec3> vs{Vec3(0.1, -0.2, 1e-300)};
  const std::vector<Vec3> vback = vec3s_from_json(nlohmann::json::parse(json_vec3s(vs).dump()));
  ASSERT_EQ(vback.size(), 1u);
  EXPECT_EQ(bits(vback[0].z()), bits(1e-300));
}

TEST(JsonNumbers, AnythingElseIsRefusedSayingWhatWasExpected) {
  try {
    number_from_json("infinity");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("expected a number, \"nan\", \"inf\" or \"-inf\", got \"infinity\""),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(vec3s_from_json(nlohmann::json::parse("[[1, 2]]")), std::runtime_error);
}

}  // namespace
}  // namespace ratchet

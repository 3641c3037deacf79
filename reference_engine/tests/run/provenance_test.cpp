// run.json's provenance (run/provenance.hpp): the date in UTC, this host, the command
// line as given (null from code), and a resumed run's record of each invocation.
#include "ratchet/run/provenance.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>
#include <ctime>
#include <regex>

namespace ratchet {
namespace {

using nlohmann::json;

TEST(Provenance, DateHostAndCommandLineOfThisInvocation) {
  const std::time_t before = std::time(nullptr);
  const json r = invocation_record({"ratchet", "run", "a b.json", "--out", "x"});
  const std::time_t after = std::time(nullptr);
  const std::string date = r.at("date_utc");
  ASSERT_TRUE(std::regex_match(date, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)"))) << date;
  // The date is now, in UTC: between the clock readings around the call.
  std::tm utc{};
  ASSERT_NE(strptime(date.c_str(), "%Y-%m-%dT%H:%M:%SZ", &utc), nullptr);
  const std::time_t t = timegm(&utc);
  EXPECT_LE(before, t);
  EXPECT_LE(t, after);
  char host[HOST_NAME_MAX + 1] = {};
  ASSERT_EQ(gethostname(host, HOST_NAME_MAX), 0);
  EXPECT_EQ(r.at("host"), std::string(host));
  EXPECT_EQ(host_name(), std::string(host));
  // Each argument as one string: one with a space stays whole.
  EXPECT_EQ(r.at("command_line"), json({"ratchet", "run", "a b.json", "--out", "x"}));
  EXPECT_TRUE(invocation_record({}).at("command_line").is_null());  // a run started from code
}

TEST(Provenance, AResumedRunKeepsItsStartAndListsEachResume) {
  const json start = {{"date_utc", "2026-01-01T00:00:00Z"}, {"host", "a"}, {"command_line", {"ratchet", "run"}}};
  const json first = {{"date_utc", "2026-01-02T00:00:00Z"}, {"host", "b"}, {"command_line", {"ratchet", "run", "--resume"}}};
  const json second = {{"date_utc", "2026-01-03T00:00:00Z"}, {"host", "c"}, {"command_line", nullptr}};
  const json p = resumed_provenance(resumed_provenance(start, first), second);
  EXPECT_EQ(p.at("date_utc"), "2026-01-01T00:00:00Z");
  EXPECT_EQ(p.at("host"), "a");
  EXPECT_EQ(p.at("resumed"), json({first, second}));
  // A checkpoint that kept no provenance: only the resumes are known.
  EXPECT_EQ(resumed_provenance(json(), first), json({{"resumed", {first}}}));
}

}  // namespace
}  // namespace ratchet

// Where, when and how a run was made: run.json "provenance" (docs/output-format.md,
// "run.json"). Decided by the clock and the invocation, not by the scene: tests that
// compare two runs' run.json leave it out, as they leave out the timings.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ratchet {

// This machine's host name (gethostname), "unknown" if it has none.
std::string host_name();

// {"date_utc": now as 2026-11-26T02:58:01Z, "host": host_name(), "command_line": the
// program's arguments, argv[0] first}. An empty command line (a run started from code,
// not from the program) is written as null.
nlohmann::json invocation_record(const std::vector<std::string>& command_line);

// A resumed run's provenance: the record of the invocation that started it, with the
// records of the invocations that resumed it, in order, under "resumed".
nlohmann::json resumed_provenance(nlohmann::json started, const nlohmann::json& invocation);

}  // namespace ratchet

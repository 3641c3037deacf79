#include "ratchet/run/provenance.hpp"

#include <unistd.h>

#include <climits>

#include "ratchet/run/runner.hpp"  // utc_stamp

namespace ratchet {

std::string host_name() {
  char buf[HOST_NAME_MAX + 1] = {};
  if (gethostname(buf, sizeof buf - 1) != 0 || buf[0] == '\0') return "unknown";
  return buf;
}

nlohmann::json invocation_record(const std::vector<std::string>& command_line) {
  return {{"date_utc", utc_stamp()},
          {"host", host_name()},
          {"command_line", command_line.empty() ? nlohmann::json(nullptr) : nlohmann::json(command_line)}};
}

nlohmann::json resumed_provenance(nlohmann::json started, const nlohmann::json& invocation) {
  if (!started.is_object()) started = nlohmann::json::object();  // a checkpoint of an engine that kept none
  if (!started.contains("resumed")) started["resumed"] = nlohmann::json::array();
  started["resumed"].push_back(invocation);
  return started;
}

}  // namespace ratchet

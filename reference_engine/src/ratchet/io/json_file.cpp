#include "ratchet/io/json_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace ratchet {

namespace fs = std::filesystem;

std::string unreadable_reason(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) return "no such file";
  if (fs::is_directory(st)) return "a folder, not a file";
  // The file exists: the open itself failed (permissions, too many open files ...).
  std::ifstream probe(path);
  if (!probe && errno != 0) return std::strerror(errno);
  return "it cannot be read";
}

std::string json_error_text(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  if (!what.empty() && what.front() == '[') {
    const std::size_t end = what.find("] ");
    if (end != std::string::npos) return what.substr(end + 2);
  }
  return what;
}

nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  std::error_code ec;  // is_directory without it throws where the status cannot be read
  if (!in || fs::is_directory(path, ec)) throw JsonFileError(path + ": cannot open the " + what + " (" + unreadable_reason(path) + ")");
  try {
    return nlohmann::json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for a number beyond a double
    throw JsonFileError(path + ": not valid JSON: " + json_error_text(e));
  }
}

}  // namespace ratchet

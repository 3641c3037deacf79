// Reading a JSON input file (scene, sweep) with an error a user can act on: why the file
// cannot be opened, or where its syntax breaks, without the JSON library's internal tags.
#pragma once

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace ratchet {

struct JsonFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Why opening `path` for reading failed, e.g. "no such file", "a folder, not a file".
std::string unreadable_reason(const std::string& path);

// The library's message without its "[json.exception.parse_error.101] " tag.
std::string json_error_text(const nlohmann::json::exception& e);

// Parses `path` (comments allowed). Throws JsonFileError:
// "PATH: cannot open the WHAT (REASON)" or "PATH: not valid JSON: parse error at line L, column C: ...".
nlohmann::json read_json_file(const std::string& path, const std::string& what);

}  // namespace ratchet

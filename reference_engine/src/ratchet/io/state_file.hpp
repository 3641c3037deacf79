// A State saved bit for bit (docs/output-format.md, "State files"): binary, fixed
// little-endian layout, a header with the format version, the body count and a key,
// a JSON metadata block, the state, and a checksum over everything before it. Used
// for settled packings (run/packing.hpp). Written atomically; a truncated, corrupt or
// foreign file is refused as a whole, never loaded in part.
#pragma once

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "ratchet/world/state.hpp"

namespace ratchet {

// Any file that cannot be read as a state file, or does not belong to the scene it is
// used with. The message starts with the file name and says what is wrong.
struct StateFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Version 2 added the kept manifolds (solver.manifold_reuse); version 1 files, which
// have none, are still read.
constexpr std::uint32_t kStateFileVersion = 2;
constexpr std::uint32_t kOldestStateFileVersion = 1;

struct StateFile {
  std::string key;       // at most 16 characters (a packing key: 16 hex digits)
  nlohmann::json meta = nlohmann::json::object();  // provenance, settle record; an object
  State state;
};

// The bytes of a state file. Throws std::invalid_argument for an inconsistent State
// (per-body arrays of different lengths) or a key longer than 16 characters.
std::string encode_state_file(const StateFile& f);
// Parses and checks the bytes; `source` names the file in messages.
StateFile decode_state_file(const std::string& bytes, const std::string& source);

void write_state_file(const std::string& path, const StateFile& f);  // atomic (.partial + rename)
StateFile read_state_file(const std::string& path);

}  // namespace ratchet

// Test helper: a text file's lines.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace ratchet::test {

inline std::vector<std::string> lines_of(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

}  // namespace ratchet::test

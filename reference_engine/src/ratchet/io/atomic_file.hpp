// Atomic output: data goes to "<path>.partial" and is renamed onto <path> only when
// complete, so a killed run never leaves a file that looks finished.
#pragma once

#include <fstream>
#include <string>

namespace ratchet {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();  // an uncommitted file is removed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  const std::string& path() const { return path_; }
  void commit();  // flush, close, rename onto the final path; throws on I/O failure

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes a whole text file atomically.
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace ratchet

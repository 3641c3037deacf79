// Atomic output: data goes to "<path>.partial" and is renamed onto <path> only when
// complete, so a killed run never leaves a file that looks finished.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace ratchet {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  // Continues the "<path>.partial" of an interrupted run: cut back to `resume_at` bytes
  // (what a checkpoint recorded) and appended to. Throws std::runtime_error naming the
  // file when it is missing or shorter than that.
  AtomicFile(std::string path, std::uintmax_t resume_at);
  ~AtomicFile();  // an uncommitted file is removed, unless kept
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  const std::string& path() const { return path_; }
  void commit();  // flush, close, rename onto the final path; throws on I/O failure
  // Flushes and returns the bytes written so far (a checkpoint's resume point).
  std::uintmax_t flush_size();
  // Flushes and closes, leaving "<path>.partial" in place for a resumed run.
  void keep();

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false, kept_ = false;
};

// Writes a whole text file atomically.
void write_file_atomic(const std::string& path, const std::string& text);

}  // namespace ratchet

#include "ratchet/io/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace ratchet {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".partial") {
  out_.open(tmp_, std::ios::out | std::ios::trunc);
  if (!out_) throw std::runtime_error(tmp_ + ": cannot open for writing");
}

AtomicFile::AtomicFile(std::string path, std::uintmax_t resume_at) : path_(std::move(path)), tmp_(path_ + ".partial") {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(tmp_, ec);
  if (ec) throw std::runtime_error(tmp_ + ": cannot resume: " + ec.message());
  if (size < resume_at)
    throw std::runtime_error(tmp_ + ": cannot resume: " + std::to_string(size) + " bytes, the checkpoint expects at least " +
                             std::to_string(resume_at));
  std::filesystem::resize_file(tmp_, resume_at, ec);
  if (ec) throw std::runtime_error(tmp_ + ": cannot cut back to the checkpoint: " + ec.message());
  out_.open(tmp_, std::ios::in | std::ios::out);  // neither truncated nor forced to append
  if (!out_) throw std::runtime_error(tmp_ + ": cannot open for writing");
  out_.seekp(0, std::ios::end);
}

std::uintmax_t AtomicFile::flush_size() {
  out_.flush();
  if (!out_) throw std::runtime_error(tmp_ + ": write failed");
  return static_cast<std::uintmax_t>(out_.tellp());
}

void AtomicFile::keep() {
  out_.flush();
  out_.close();
  kept_ = true;
}

AtomicFile::~AtomicFile() {
  if (!committed_ && !kept_) {
    out_.close();
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw std::runtime_error(tmp_ + ": write failed");
  out_.close();
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) throw std::runtime_error(path_ + ": cannot rename the finished file into place");
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.stream() << text;
  f.commit();
}

}  // namespace ratchet

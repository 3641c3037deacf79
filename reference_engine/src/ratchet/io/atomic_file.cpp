#include "ratchet/io/atomic_file.hpp"

#include <cstdio>
#include <stdexcept>

namespace ratchet {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".partial") {
  out_.open(tmp_, std::ios::out | std::ios::trunc);
  if (!out_) throw std::runtime_error(tmp_ + ": cannot open for writing");
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
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

#include "check_record.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

namespace ratchet::validation {
namespace {

// The running program's name, reduced to characters that are safe in a file name.
std::string program_name() {
  // GNU libc sets this from argv[0] before main (g++ always defines _GNU_SOURCE).
  std::string name = program_invocation_short_name ? program_invocation_short_name : "";
  for (char& c : name) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '-' || c == '_' || c == '.';
    if (!safe) c = '_';
  }
  return name.empty() ? std::string("validation") : name;
}

[[noreturn]] void fail(const std::string& what, const std::string& path, int error) {
  throw std::runtime_error("ratchet::validation::record: " + what + " '" + path +
                           "' (RATCHET_CHECKS_DIR): " + std::strerror(error));
}

// Appends `line` to `path` in one write(2) on a file opened with O_APPEND, so lines
// of concurrent writers never interleave.
void append_line(const std::string& path, const std::string& line) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot open", path, errno);
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd, line.data() + done, line.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      fail("cannot write to", path, error);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail("cannot close", path, errno);
}

}  // namespace

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    if (std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;  // 17 significant digits always read back exactly
}

bool record(const std::string& case_name, const std::string& check, double measured,
            const std::string& expected, const std::string& tolerance, bool passed,
            const std::string& reason) {
  const bool finite = std::isfinite(measured);
  passed = passed && finite;

  const char* dir = std::getenv("RATCHET_CHECKS_DIR");
  if (dir == nullptr || *dir == '\0') return passed;

  nlohmann::ordered_json line;
  line["case"] = case_name;
  line["check"] = check;
  // nlohmann::json writes doubles in the shortest form that reads back exactly
  // (at most 17 significant digits); JSON has no NaN or Inf, hence null.
  line["measured"] = finite ? nlohmann::ordered_json(measured) : nlohmann::ordered_json(nullptr);
  line["expected"] = expected;
  line["tolerance"] = tolerance;
  line["reason"] = reason;
  line["passed"] = passed;

  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) fail("cannot create the folder", dir, error.value());
  const std::string path = (std::filesystem::path(dir) /
                            (program_name() + "-" + std::to_string(::getpid()) + ".jsonl"))
                               .string();
  append_line(path, line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
                        "\n");
  return passed;
}

bool check_near(const std::string& case_name, const std::string& check, double measured,
                double expected, double abs_tol, const std::string& reason) {
  const bool passed = std::fabs(measured - expected) <= abs_tol;
  return record(case_name, check, measured, format_number(expected),
                "abs " + format_number(abs_tol), passed, reason);
}

bool check_rel(const std::string& case_name, const std::string& check, double measured,
               double expected, double rel_tol, const std::string& reason) {
  const bool passed = std::fabs(measured - expected) <= rel_tol * std::fabs(expected);
  return record(case_name, check, measured, format_number(expected),
                "rel " + format_number(rel_tol), passed, reason);
}

bool check_le(const std::string& case_name, const std::string& check, double measured,
              double bound, const std::string& reason) {
  const bool passed = measured <= bound;
  return record(case_name, check, measured, "<= " + format_number(bound), "upper bound", passed,
                reason);
}

}  // namespace ratchet::validation

// libFuzzer target: the scene reader (scene/scene.hpp: load_scene, build_scene,
// apply_override). docs/validation.md s. 9.
//
// Input bytes: the scene file, then optionally NUL-separated `--set` assignments:
//   <scene JSON> [\0 key.path=value]*
// The scene text goes into an in-memory file (memfd, read back by load_scene through
// /proc/self/fd/N, so nothing touches the disk) and load_scene runs with the
// assignments as its overrides: the same path as `ratchet run scene.json --set ...`.
//
// Property: load_scene returns a SceneDef, or throws SceneError whose message names a
// field ("field '...'"), the --set that is malformed ("--set '...'") or says the file is
// not valid JSON. Anything else (another exception type, a crash, a sanitizer report,
// a hang caught by -timeout) is a finding.
//
// Size cap: a valid scene may ask for 10^7 generated particles of 10^4 vertices each
// (the reader's own limits), which is a valid but long build, not a bug. Before calling
// the reader, the harness applies the overrides to its own copy of the JSON and skips
// the input (returns without calling load_scene) if particles.generate.count or
// .vertices, the number of listed bodies, or a body's vertex list exceeds kCap = 64.
// Nothing else is capped: a small scene that still takes long is a finding.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/scene/scene.hpp"

namespace {

using nlohmann::json;
constexpr long long kCap = 64;

bool over_cap(const json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) return false;
  const json& v = j.at(key);
  if (v.is_number_integer()) return v.get<long long>() > kCap || v.get<long long>() < -kCap;
  if (v.is_number_unsigned()) return v.get<unsigned long long>() > static_cast<unsigned long long>(kCap);
  if (v.is_array()) return v.size() > static_cast<std::size_t>(kCap);
  return false;
}

// True if building the scene would be large (see the file comment).
bool too_big(const json& scene) {
  if (!scene.is_object() || !scene.contains("particles")) return false;
  const json& p = scene.at("particles");
  if (!p.is_object()) return false;
  if (p.contains("generate") && (over_cap(p.at("generate"), "count") || over_cap(p.at("generate"), "vertices")))
    return true;
  if (over_cap(p, "bodies")) return true;
  if (p.contains("bodies") && p.at("bodies").is_array())
    for (const json& b : p.at("bodies"))
      if (over_cap(b, "vertices")) return true;
  return false;
}

bool names_a_field(const std::string& msg) {
  return msg.find("field '") != std::string::npos || msg.find("--set '") != std::string::npos ||
         msg.find("not valid JSON") != std::string::npos;
}

[[noreturn]] void violation(const std::string& what) {
  std::fprintf(stderr, "scene_fuzz: PROPERTY VIOLATED: %s\n", what.c_str());
  std::abort();
}

int scene_fd() {
  static const int fd = memfd_create("scene_fuzz.json", 0);
  if (fd < 0) {
    std::perror("memfd_create");
    std::abort();
  }
  return fd;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const std::size_t nul = bytes.find('\0', start);
    parts.push_back(bytes.substr(start, nul == std::string::npos ? std::string::npos : nul - start));
    if (nul == std::string::npos) break;
    start = nul + 1;
  }
  const std::string text = parts[0];
  const std::vector<std::string> overrides(parts.begin() + 1, parts.end());

  // The cap check, on the harness's own copy (a parse or override error is left for the
  // reader to report).
  {
    json j = json::parse(text, nullptr, false, /*ignore_comments=*/true);
    if (!j.is_discarded()) {
      try {
        for (const std::string& o : overrides) ratchet::apply_override(j, o, "cap-check");
      } catch (const ratchet::SceneError&) {
      }
      if (too_big(j)) return 0;
    }
  }

  const int fd = scene_fd();
  if (ftruncate(fd, 0) != 0 || pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size())) {
    std::perror("scene_fuzz: memfd write");
    std::abort();
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  try {
    const ratchet::SceneDef s = ratchet::load_scene(path, overrides);
    if (s.bodies.empty()) violation("a scene without bodies was accepted");
    if (!(s.dt > 0.0) || s.steps < 1) violation("a scene without a positive step count was accepted");
  } catch (const ratchet::SceneError& e) {
    if (!names_a_field(e.what())) violation(std::string("SceneError without a field: ") + e.what());
  } catch (const std::exception& e) {
    violation(std::string("undocumented exception: ") + e.what());
  } catch (...) {
    violation("undocumented non-std exception");
  }
  return 0;
}

// Private to scene/ (scene_detail.hpp lists its files): the reading context every
// section reader checks its fields with.
#pragma once

#include <functional>
#include <initializer_list>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "ratchet/scene/scene.hpp"

namespace ratchet::scene_detail {

using nlohmann::json;

// Reading context: every error names where the value came from (the file, or the
// --set option that put it there), the field (dotted path) and what was expected, and
// shows what was found.
struct Reader {
  std::string source;
  // Where the value of a field came from; empty: always `source`.
  std::function<std::string(const std::string& field)> origin_of;
  // The effective scene (SceneDef::effective): every field read with a default that the
  // scene lacks is written into it with that default. Null: not recorded.
  json* effective = nullptr;

  std::string where(const std::string& field) const { return origin_of ? origin_of(field) : source; }

  [[noreturn]] void fail(const std::string& field, const std::string& expected, const json* got = nullptr) const;

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  // j is an object whose keys are all in `allowed` (an unknown one is named with the
  // closest known name, if one is close enough to be a typo).
  void object(const json& j, const std::string& path, std::initializer_list<const char*> allowed) const;

  // Records `value` as the effective value of path.key when the scene lacks the field.
  void fill(const std::string& path, const std::string& key, const json& value) const;

  // The field path.key, or def when it is absent (recorded with fill); each checks the
  // value's type and range.
  double number(const json& j, const std::string& path, const std::string& key, double def, double lo, double hi,
                bool lo_open, bool hi_open, const std::string& expected) const;
  double positive(const json& j, const std::string& path, const std::string& key, double def) const;
  double non_negative(const json& j, const std::string& path, const std::string& key, double def) const;
  double finite(const json& j, const std::string& path, const std::string& key, double def) const;
  long long integer(const json& j, const std::string& path, const std::string& key, long long def, long long lo,
                    long long hi) const;
  bool boolean(const json& j, const std::string& path, const std::string& key, bool def) const;
  std::string string(const json& j, const std::string& path, const std::string& key, const std::string& def) const;
  // One of a set of names (each a JSON string and the value it stands for); def when absent.
  template <class E>
  E choice(const json& j, const std::string& path, const std::string& key, E def,
           std::initializer_list<std::pair<const char*, E>> names) const {
    std::string expected;  // "a" or "b"; "a", "b" or "c"
    const char* def_name = nullptr;
    std::size_t i = 0;
    for (const auto& [name, value] : names) {
      expected += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("\"" + std::string(name) + "\"");
      if (value == def) def_name = name;
      ++i;
    }
    if (!j.contains(key)) {
      fill(path, key, def_name);
      return def;
    }
    const json& v = j.at(key);
    for (const auto& [name, value] : names)
      if (v == name) return value;
    fail(join(path, key), expected, &v);
  }
  Vec3 vec3(const json& v, const std::string& f) const;
  Vec3 vec3(const json& j, const std::string& path, const std::string& key, const Vec3& def) const;
  const json& required(const json& j, const std::string& path, const std::string& key,
                       const std::string& expected) const;
};

}  // namespace ratchet::scene_detail

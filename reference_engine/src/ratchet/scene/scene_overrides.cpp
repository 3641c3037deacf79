// The --set overrides (docs/cli.md): "key.path=value" written into the scene JSON, and
// for each field the origin an error names: the --set that put its value there, or
// the file.
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "ratchet/scene/scene_detail.hpp"

namespace ratchet {

using nlohmann::json;

void apply_override(json& scene, const std::string& assignment, const std::string& source) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(source + ": --set '" + assignment + "': expected key.path=value");
  const std::string path = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  json value = json::parse(text, nullptr, false);
  if (value.is_discarded()) value = text;  // not JSON: a plain string
  json* node = &scene;
  std::stringstream ss(path);
  std::string key;
  while (std::getline(ss, key, '.')) {
    if (key.empty()) throw SceneError(source + ": --set '" + assignment + "': empty key in the path");
    if (node->is_null()) *node = json::object();  // a section the scene leaves to its defaults
    if (!node->is_object()) throw SceneError(source + ": --set '" + assignment + "': '" + key + "' is inside a non-object");
    node = &(*node)[key];
  }
  *node = value;
}

namespace scene_detail {

namespace {

// The field's JSON pointer: "a.b[2].c" -> /a/b/2/c; "(top level)" -> the root.
json::json_pointer pointer_of(const std::string& field) {
  std::string ptr;
  if (field != "(top level)")
    for (char c : field) {
      if (c == '.' || c == '[') ptr += '/';
      else if (c == '~') ptr += "~0";
      else if (c == '/') ptr += "~1";
      else if (c != ']') ptr += c;
    }
  return json::json_pointer(ptr.empty() ? "" : "/" + ptr);
}

// "a.b[2]" -> "a.b", "a.b" -> "a", "a" -> "".
std::string parent_of(const std::string& field) {
  const auto cut = field.find_last_of(".[");
  return cut == std::string::npos ? "" : field.substr(0, cut);
}

// True when `inner` is `outer` or a field inside it (dotted path with [i] elements).
bool within(const std::string& inner, const std::string& outer) {
  return inner.size() >= outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
         (inner.size() == outer.size() || inner[outer.size()] == '.' || inner[outer.size()] == '[');
}


}  // namespace

// An error in a value that a --set put there names that --set, not the file: the
// field is the --set's key or inside it, or the file lacks the field and a --set made
// its outermost missing section (--set settle.max_time=5 makes 'settle').
std::function<std::string(const std::string& field)> override_origin(json file, std::vector<std::string> overrides,
                                                                     std::string path) {
  return [file = std::move(file), overrides = std::move(overrides), path = std::move(path)](const std::string& field) -> std::string {
    std::string made = field;  // the outermost section on the way to `field` that the file lacks
    if (!file.contains(pointer_of(field)))
      for (std::string up = parent_of(made); !up.empty() && !file.contains(pointer_of(up)); up = parent_of(up)) made = up;
    else
      made.clear();
    for (auto o = overrides.rbegin(); o != overrides.rend(); ++o) {
      const std::string key = o->substr(0, o->find('='));
      if (within(field, key) || (!made.empty() && within(key, made)))
        return "--set " + *o + " (command-line option, applied to " + path + ")";
    }
    return path;
  };
}

}  // namespace scene_detail

}  // namespace ratchet

#include "scene_input.hpp"

#include <nlohmann/json.hpp>

#include "ratchet/io/json_file.hpp"

namespace ratchet_python {

ratchet::SceneDef scene_from_file(const std::string& path, const std::vector<std::string>& overrides) {
  return ratchet::load_scene(path, overrides);
}

ratchet::SceneDef scene_from_json(const std::string& text, const std::string& source,
                                  const std::vector<std::string>& overrides) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // the package dumps the dict itself: only values JSON cannot hold
    throw ratchet::SceneError(source + ": not valid JSON: " + ratchet::json_error_text(e));
  }
  for (const std::string& o : overrides) ratchet::apply_override(j, o, source);
  return ratchet::build_scene(j, source);
}

}  // namespace ratchet_python

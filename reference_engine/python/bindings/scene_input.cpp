#include "scene_input.hpp"

#include <nlohmann/json.hpp>

namespace ratchet_python {

ratchet::SceneDef scene_from_file(const std::string& path, const std::vector<std::string>& overrides) {
  return ratchet::load_scene(path, overrides);
}

ratchet::SceneDef scene_from_json(const std::string& text, const std::string& source,
                                  const std::vector<std::string>& overrides) {
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  // The package dumps the dict itself, so this only fails for values JSON cannot hold.
  if (j.is_discarded()) throw ratchet::SceneError(source + ": not valid JSON");
  for (const std::string& o : overrides) ratchet::apply_override(j, o, source);
  return ratchet::build_scene(j, source);
}

}  // namespace ratchet_python

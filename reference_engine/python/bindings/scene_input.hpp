// A scene for the Python module: read by the engine's own scene reader, so a bad scene
// raises the message `ratchet run` prints (the file or origin, the field, what was expected).
#pragma once

#include <string>
#include <vector>

#include "ratchet/scene/scene.hpp"

namespace ratchet_python {

// A scene file, with `--set`-style overrides ("solver.p_gap=0.05").
ratchet::SceneDef scene_from_file(const std::string& path, const std::vector<std::string>& overrides);

// A scene given as JSON text (a Python dict dumped by the package); `source` names it in errors.
ratchet::SceneDef scene_from_json(const std::string& text, const std::string& source,
                                  const std::vector<std::string>& overrides);

}  // namespace ratchet_python

#include "ratchet/run/sweep_points.hpp"

#include "ratchet/scene/scene.hpp"  // SceneError

namespace ratchet {

using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& expected,
                       const json* got = nullptr) {
  std::string msg = source + ": field '" + field + "': expected " + expected;
  if (got != nullptr) {
    std::string shown = got->dump();
    if (shown.size() > 80) shown = shown.substr(0, 77) + "...";
    msg += ", got " + shown;
  }
  throw SceneError(msg);
}

std::string key_list(const std::vector<std::string>& keys) {
  std::string s;
  for (const std::string& k : keys) s += (s.empty() ? "" : ", ") + k;
  return s;
}

std::vector<std::vector<json>> grid_points(const json& grid, const std::string& source,
                                           std::vector<std::string>& keys) {
  if (!grid.is_object()) fail(source, "grid", "an object {\"dotted.path\": [values ...]}", &grid);
  std::vector<std::vector<json>> values;
  for (auto it = grid.begin(); it != grid.end(); ++it) {  // nlohmann's objects iterate in sorted order
    if (!it.value().is_array() || it.value().empty())
      fail(source, "grid." + it.key(), "a non-empty list of values", &it.value());
    keys.push_back(it.key());
    values.emplace_back(it.value().begin(), it.value().end());
  }
  std::vector<std::vector<json>> points;
  std::vector<std::size_t> index(values.size(), 0);
  for (bool more = true; more;) {
    std::vector<json> point;
    for (std::size_t k = 0; k < values.size(); ++k) point.push_back(values[k][index[k]]);
    points.push_back(std::move(point));
    more = false;
    for (std::size_t k = values.size(); k-- > 0;) {  // odometer, last key fastest
      if (++index[k] < values[k].size()) {
        more = true;
        break;
      }
      index[k] = 0;
    }
  }
  return points;
}

std::vector<std::vector<json>> listed_points(const json& list, const std::string& source,
                                             std::vector<std::string>& keys) {
  const std::string expected = "a non-empty list of points {\"dotted.path\": value, ...}";
  if (!list.is_array() || list.empty()) fail(source, "points", expected, &list);
  std::vector<std::vector<json>> points;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string field = "points[" + std::to_string(i) + "]";
    const json& p = list[i];
    if (!p.is_object() || p.empty()) fail(source, field, "a non-empty object {\"dotted.path\": value, ...}", &p);
    std::vector<std::string> mine;
    for (auto it = p.begin(); it != p.end(); ++it) mine.push_back(it.key());
    if (i == 0) keys = mine;
    // The same keys everywhere: each is a column of summary.csv.
    if (mine != keys)
      fail(source, field, "the fields of points[0] (" + key_list(keys) + "), got " + key_list(mine));
    std::vector<json> point;
    for (const std::string& k : keys) point.push_back(p.at(k));
    for (std::size_t e = 0; e < points.size(); ++e)
      if (points[e] == point)
        fail(source, field, "a point not listed before (it is points[" + std::to_string(e) + "] again)", &p);
    points.push_back(std::move(point));
  }
  return points;
}

}  // namespace

std::vector<std::vector<json>> sweep_points(const json& sweep, const std::string& source,
                                            std::vector<std::string>& keys) {
  keys.clear();
  if (sweep.contains("grid") && sweep.contains("points"))
    fail(source, "points", "either a grid or a list of points, not both");
  if (sweep.contains("points")) return listed_points(sweep.at("points"), source, keys);
  if (sweep.contains("grid")) return grid_points(sweep.at("grid"), source, keys);
  return {std::vector<json>()};
}

}  // namespace ratchet

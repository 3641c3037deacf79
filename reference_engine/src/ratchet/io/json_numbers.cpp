#include "ratchet/io/json_numbers.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace ratchet {

nlohmann::json json_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

double number_from_json(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return HUGE_VAL;
    if (s == "-inf") return -HUGE_VAL;
  }
  throw std::runtime_error("expected a number, \"nan\", \"inf\" or \"-inf\", got " + j.dump());
}

nlohmann::json json_numbers(const std::vector<double>& xs) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : xs) a.push_back(json_number(x));
  return a;
}

std::vector<double> numbers_from_json(const nlohmann::json& j) {
  std::vector<double> xs;
  xs.reserve(j.size());
  for (const auto& e : j) xs.push_back(number_from_json(e));
  return xs;
}

nlohmann::json json_vec3s(const std::vector<Vec3>& vs) {
  nlohmann::json a = nlohmann::json::array();
  for (const Vec3& v : vs) a.push_back({json_number(v.x()), json_number(v.y()), json_number(v.z())});
  return a;
}

std::vector<Vec3> vec3s_from_json(const nlohmann::json& j) {
  std::vector<Vec3> vs;
  vs.reserve(j.size());
  for (const auto& e : j) {
    if (!e.is_array() || e.size() != 3) throw std::runtime_error("expected [x, y, z], got " + e.dump());
    vs.emplace_back(number_from_json(e[0]), number_from_json(e[1]), number_from_json(e[2]));
  }
  return vs;
}

}  // namespace ratchet

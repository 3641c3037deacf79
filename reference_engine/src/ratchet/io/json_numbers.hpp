// Doubles in JSON bit for bit, for checkpoints (run/checkpoint.hpp). nlohmann writes a
// finite double in the shortest form that reads back to the same bits, but JSON has no
// NaN or infinity (nlohmann writes them as null): they go as "nan", "inf" and "-inf".
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "ratchet/core/types.hpp"

namespace ratchet {

nlohmann::json json_number(double x);
// Throws std::runtime_error for anything but a number or one of the three strings.
double number_from_json(const nlohmann::json& j);

nlohmann::json json_numbers(const std::vector<double>& xs);
std::vector<double> numbers_from_json(const nlohmann::json& j);

// Vec3 as [x, y, z].
nlohmann::json json_vec3s(const std::vector<Vec3>& vs);
std::vector<Vec3> vec3s_from_json(const nlohmann::json& j);

}  // namespace ratchet

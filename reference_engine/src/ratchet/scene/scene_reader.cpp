#include "ratchet/scene/scene_reader.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ratchet::scene_detail {

namespace {

// Optimal string alignment distance (a transposition counts as one edit): how far a
// mistyped field name is from a known one.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t k = 0; k <= b.size(); ++k) d[0][k] = k;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t k = 1; k <= b.size(); ++k) {
      const std::size_t cost = a[i - 1] == b[k - 1] ? 0 : 1;
      d[i][k] = std::min({d[i - 1][k] + 1, d[i][k - 1] + 1, d[i - 1][k - 1] + cost});
      if (i > 1 && k > 1 && a[i - 1] == b[k - 2] && a[i - 2] == b[k - 1]) d[i][k] = std::min(d[i][k], d[i - 2][k - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The known name closest to `unknown`, or "" when none is close enough to be a typo
// (at most 2 edits, and at most a third of the name).
std::string closest_name(const std::string& unknown, std::initializer_list<const char*> known) {
  const std::size_t limit = std::max<std::size_t>(1, std::min<std::size_t>(2, unknown.size() / 3));
  std::string best;
  std::size_t best_d = limit + 1;
  for (const char* k : known) {
    const std::size_t d = edit_distance(unknown, k);
    if (d < best_d) best_d = d, best = k;
  }
  return best;
}

// A field's dotted path ("particles.bodies[3].velocity") as a JSON pointer
// ("/particles/bodies/3/velocity"); scene keys hold no '/', '~', '.' or '['.
json::json_pointer pointer_of(const std::string& field) {
  std::string ptr;
  for (char c : field) {
    if (c == '.' || c == '[') ptr += '/';
    else if (c != ']') ptr += c;
  }
  return json::json_pointer("/" + ptr);
}

}  // namespace

void Reader::fill(const std::string& path, const std::string& key, const json& value) const {
  if (effective == nullptr) return;
  const json::json_pointer ptr = pointer_of(join(path, key));
  if (!effective->contains(ptr)) (*effective)[ptr] = value;
}

void Reader::fail(const std::string& field, const std::string& expected, const json* got) const {
  std::string msg = where(field) + ": field '" + field + "': expected " + expected;
  if (got != nullptr) {
    std::string shown = got->dump();
    if (shown.size() > 80) shown = shown.substr(0, 77) + "...";
    msg += ", got " + shown;
  }
  throw SceneError(msg);
}

void Reader::object(const json& j, const std::string& path, std::initializer_list<const char*> allowed) const {
  if (!j.is_object()) fail(path.empty() ? "(top level)" : path, "an object", &j);
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* a : allowed) known = known || it.key() == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      const std::string field = join(path, it.key()), near = closest_name(it.key(), allowed);
      throw SceneError(where(field) + ": field '" + field + "': unknown field" +
                       (near.empty() ? "" : ", did you mean '" + join(path, near) + "'?") +
                       " (known fields here: " + list + ")");
    }
  }
}

double Reader::number(const json& j, const std::string& path, const std::string& key, double def, double lo,
                      double hi, bool lo_open, bool hi_open, const std::string& expected) const {
  if (!j.contains(key)) {
    fill(path, key, def);
    return def;
  }
  const json& v = j.at(key);
  const std::string f = join(path, key);
  if (!v.is_number()) fail(f, expected, &v);
  const double x = v.get<double>();
  const bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  if (!ok) fail(f, expected, &v);
  return x;
}

double Reader::positive(const json& j, const std::string& path, const std::string& key, double def) const {
  return number(j, path, key, def, 0.0, HUGE_VAL, true, false, "a finite positive number");
}

double Reader::non_negative(const json& j, const std::string& path, const std::string& key, double def) const {
  return number(j, path, key, def, 0.0, HUGE_VAL, false, false, "a finite number >= 0");
}

double Reader::finite(const json& j, const std::string& path, const std::string& key, double def) const {
  return number(j, path, key, def, -HUGE_VAL, HUGE_VAL, false, false, "a finite number");
}

long long Reader::integer(const json& j, const std::string& path, const std::string& key, long long def,
                          long long lo, long long hi) const {
  if (!j.contains(key)) {
    fill(path, key, def);
    return def;
  }
  const json& v = j.at(key);
  const std::string expected = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (!v.is_number_integer()) fail(join(path, key), expected, &v);
  const long long x = v.get<long long>();
  if (x < lo || x > hi) fail(join(path, key), expected, &v);
  return x;
}

bool Reader::boolean(const json& j, const std::string& path, const std::string& key, bool def) const {
  if (!j.contains(key)) {
    fill(path, key, def);
    return def;
  }
  const json& v = j.at(key);
  if (!v.is_boolean()) fail(join(path, key), "true or false", &v);
  return v.get<bool>();
}

std::string Reader::string(const json& j, const std::string& path, const std::string& key,
                           const std::string& def) const {
  if (!j.contains(key)) {
    fill(path, key, def);
    return def;
  }
  const json& v = j.at(key);
  if (!v.is_string()) fail(join(path, key), "a string", &v);
  return v.get<std::string>();
}

Vec3 Reader::vec3(const json& v, const std::string& f) const {
  if (!v.is_array() || v.size() != 3) fail(f, "an array of 3 finite numbers", &v);
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v[static_cast<std::size_t>(i)].is_number()) fail(f, "an array of 3 finite numbers", &v);
    out[i] = v[static_cast<std::size_t>(i)].get<double>();
    if (!std::isfinite(out[i])) fail(f, "an array of 3 finite numbers", &v);
  }
  return out;
}

Vec3 Reader::vec3(const json& j, const std::string& path, const std::string& key, const Vec3& def) const {
  if (j.contains(key)) return vec3(j.at(key), join(path, key));
  fill(path, key, json::array({def.x(), def.y(), def.z()}));
  return def;
}

const json& Reader::required(const json& j, const std::string& path, const std::string& key,
                             const std::string& expected) const {
  if (!j.contains(key)) fail(join(path, key), expected + " (the field is required)");
  return j.at(key);
}

}  // namespace ratchet::scene_detail

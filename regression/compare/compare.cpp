// The golden-curve comparison rule (compare.hpp; the Python twin is
// scripts/regression/compare.py, the rule is stated in docs/regression.md).
#include "compare/compare.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace ratchet::regression {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean_of(const std::vector<double>& xs) {
  double s = 0.0;
  for (double x : xs) s += x;
  return s / static_cast<double>(xs.size());
}

double sample_var(const std::vector<double>& xs, double m) {
  if (xs.size() < 2) return 0.0;
  double q = 0.0;
  for (double x : xs) {
    const double d = x - m;
    q += d * d;
  }
  return q / static_cast<double>(xs.size() - 1);
}

// Fills n, failures, mean, std, max, worst_row, passed from the per-row errors.
void summarize(ColumnResult& r, const std::vector<double>& errs) {
  r.n = errs.size();
  if (errs.empty()) return;
  std::size_t worst = 0;
  bool any_inf = false;
  for (std::size_t i = 0; i < errs.size(); ++i) {
    if (errs[i] > errs[worst]) worst = i;
    if (!within(errs[i], r.tol, r.scale)) ++r.failures;
    if (std::isinf(errs[i])) any_inf = true;
  }
  r.worst_row = static_cast<long>(worst);
  r.max = errs[worst];
  if (any_inf) {
    r.mean = r.std = kInf;
  } else {
    r.mean = mean_of(errs);
    double q = 0.0;
    for (double e : errs) {
      const double d = e - r.mean;
      q += d * d;
    }
    r.std = std::sqrt(q / static_cast<double>(errs.size()));
  }
  r.passed = r.failures == 0;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  if (line.empty()) out.emplace_back();
  return out;
}

std::string join(const std::vector<std::string>& xs, const std::string& sep) {
  std::string s;
  for (std::size_t i = 0; i < xs.size(); ++i) s += (i ? sep : "") + xs[i];
  return s;
}

// "%.3g" as Python prints it for floats (nan, inf, -inf spelled out); integral key
// values as integers, like the Python report.
std::string g3(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}
std::string key_text(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::fabs(x) < 9007199254740992.0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(x));
    return buf;
  }
  return g3(x);
}
std::string g17(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

}  // namespace

// --- The rule ------------------------------------------------------------------------

double value_error(double a, double b, double floor) {
  if (a == b || (std::isnan(a) && std::isnan(b))) return 0.0;
  if (!std::isfinite(a) || !std::isfinite(b)) return kInf;
  const double denom = std::max(std::fabs(b), floor);
  if (denom == 0.0) return kInf;  // floor > 0 in a valid manifest
  return std::fabs(a - b) / denom;
}

EnsembleValue ensemble_error(const std::vector<double>& new_values, const std::vector<double>& golden_values,
                             double floor) {
  if (new_values.empty() || golden_values.empty())
    throw std::invalid_argument("an ensemble needs at least one realization on each side");
  std::vector<double> all(new_values);
  all.insert(all.end(), golden_values.begin(), golden_values.end());
  if (!std::all_of(all.begin(), all.end(), [](double v) { return std::isfinite(v); })) {
    if (std::all_of(all.begin(), all.end(), [](double v) { return std::isnan(v); })) return {0.0, kNaN, kNaN, 0.0};
    const double v0 = all.front();
    if (std::isinf(v0) && std::all_of(all.begin(), all.end(), [v0](double v) { return v == v0; }))
      return {0.0, v0, v0, 0.0};
    return {kInf, kNaN, kNaN, kNaN};
  }
  const double ma = mean_of(new_values), mb = mean_of(golden_values);
  const double se = std::sqrt(sample_var(new_values, ma) / static_cast<double>(new_values.size()) +
                              sample_var(golden_values, mb) / static_cast<double>(golden_values.size()));
  const double denom = std::max(se, floor);
  const double err = ma == mb ? 0.0 : (denom > 0.0 ? std::fabs(ma - mb) / denom : kInf);
  return {err, ma, mb, se};
}

namespace {
ColumnResult new_result(const std::string& table, const std::string& column, const char* kind, double tol,
                        double floor, double scale) {
  ColumnResult r;
  r.table = table;
  r.column = column;
  r.kind = kind;
  r.tol = tol;
  r.floor = floor;
  r.scale = scale;
  return r;
}
}  // namespace

ColumnResult compare_deterministic(const std::string& column, const std::vector<double>& new_values,
                                   const std::vector<double>& golden_values, double tol, double floor,
                                   double scale, const std::vector<std::vector<double>>& keys,
                                   const std::string& table) {
  if (new_values.size() != golden_values.size())
    throw std::invalid_argument("column '" + column + "': " + std::to_string(new_values.size()) +
                                " new rows against " + std::to_string(golden_values.size()) + " golden rows");
  ColumnResult r = new_result(table, column, "deterministic", tol, floor, scale);
  std::vector<double> errs(new_values.size());
  for (std::size_t i = 0; i < errs.size(); ++i) errs[i] = value_error(new_values[i], golden_values[i], floor);
  summarize(r, errs);
  if (r.worst_row >= 0) {
    const auto w = static_cast<std::size_t>(r.worst_row);
    r.worst_new = new_values[w];
    r.worst_golden = golden_values[w];
    if (w < keys.size()) r.worst_key = keys[w];
  }
  return r;
}

ColumnResult compare_ensemble(const std::string& column, const std::vector<std::vector<double>>& new_values,
                              const std::vector<std::vector<double>>& golden_values, double k, double floor,
                              double scale, const std::vector<std::vector<double>>& keys,
                              const std::string& table) {
  if (new_values.empty() || golden_values.empty())
    throw std::invalid_argument("column '" + column + "': an ensemble needs at least one realization on each side");
  const std::size_t rows = golden_values.front().size();
  for (const auto* side : {&new_values, &golden_values})
    for (const auto& real : *side)
      if (real.size() != rows)
        throw std::invalid_argument("column '" + column + "': realizations with different row counts");
  ColumnResult r = new_result(table, column, "ensemble", k, floor, scale);
  std::vector<EnsembleValue> values;
  std::vector<double> errs;
  for (std::size_t i = 0; i < rows; ++i) {
    std::vector<double> a, b;
    for (const auto& real : new_values) a.push_back(real[i]);
    for (const auto& real : golden_values) b.push_back(real[i]);
    values.push_back(ensemble_error(a, b, floor));
    errs.push_back(values.back().err);
  }
  summarize(r, errs);
  if (r.worst_row >= 0) {
    const auto w = static_cast<std::size_t>(r.worst_row);
    r.worst_new = values[w].mean_new;
    r.worst_golden = values[w].mean_golden;
    r.worst_se = values[w].se;
    if (w < keys.size()) r.worst_key = keys[w];
  }
  return r;
}

long first_key_mismatch(const std::vector<std::vector<double>>& new_keys,
                        const std::vector<std::vector<double>>& golden_keys) {
  const std::size_t n = std::min(new_keys.size(), golden_keys.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = std::min(new_keys[i].size(), golden_keys[i].size());
    for (std::size_t j = 0; j < m; ++j)
      if (value_error(new_keys[i][j], golden_keys[i][j], kKeyFloor) > kKeyTol) return static_cast<long>(i);
  }
  return -1;
}

// --- CSV tables ----------------------------------------------------------------------------

bool parse_cell(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) {
    out = kNaN;
    return true;
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size()) return false;
  out = v;  // overflow gives +-HUGE_VAL = inf, as Python's float() does
  return true;
}

std::vector<double> Table::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end())
    throw TableError(path + ": no column '" + name + "' (columns: " + join(header, ", ") + ")");
  const auto j = static_cast<std::size_t>(it - header.begin());
  std::vector<double> out;
  out.reserve(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double v;
    if (!parse_cell(rows[i][j], v))
      throw TableError(path + ": row " + std::to_string(i + 1) + ", column '" + name + "': not a number: '" +
                       rows[i][j] + "'");
    out.push_back(v);
  }
  return out;
}

Table read_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw TableError(path + ": missing");
  Table t;
  t.path = path;
  std::string line;
  if (!std::getline(in, line)) throw TableError(path + ": empty (no header)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  t.header = split_csv_line(line);
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    auto cells = split_csv_line(line);
    if (cells.size() != t.header.size())
      throw TableError(path + ": row " + std::to_string(t.rows.size() + 1) + " has " + std::to_string(cells.size()) +
                       " cells, the header " + std::to_string(t.header.size()));
    t.rows.push_back(std::move(cells));
  }
  return t;
}

// --- Manifest ----------------------------------------------------------------------------------

namespace {

ManifestError field_error(const std::string& path, const std::string& where, const std::string& what) {
  return ManifestError(path + ": field '" + where + "': expected " + what);
}
ManifestError field_error(const std::string& path, const std::string& where, const std::string& what,
                          const nlohmann::ordered_json& got) {
  std::string text = got.dump();
  if (text.size() > 80) text.resize(80);
  return ManifestError(path + ": field '" + where + "': expected " + what + ", got " + text);
}
bool finite_number(const nlohmann::ordered_json& x) { return x.is_number() && std::isfinite(x.get<double>()); }

}  // namespace

Manifest parse_manifest(const std::string& path, const nlohmann::ordered_json& raw) {
  if (!raw.is_object()) throw ManifestError(path + ": expected a JSON object at the top level");
  using json = nlohmann::ordered_json;
  auto need = [&](const char* key) -> const json& {
    if (!raw.contains(key)) throw field_error(path, key, "a value (the field is required)");
    return raw.at(key);
  };
  Manifest m;
  m.path = path;
  const auto& format = need("format");
  if (!(format.is_number_integer() && format.get<long long>() == 1)) throw field_error(path, "format", "1", format);
  const auto& name = need("case");
  if (!name.is_string() || name.get<std::string>().empty())
    throw field_error(path, "case", "a non-empty string", name);
  m.case_name = name.get<std::string>();
  const auto& kind = need("kind");
  if (!(kind.is_string() && (kind == "deterministic" || kind == "ensemble")))
    throw field_error(path, "kind", "\"deterministic\" or \"ensemble\"", kind);
  m.kind = kind.get<std::string>();

  const auto& reals = need("realizations");
  if (!reals.is_array() || reals.empty()) throw field_error(path, "realizations", "a non-empty list", reals);
  if (m.kind == "deterministic" && reals.size() != 1)
    throw field_error(path, "realizations", "exactly one realization for a deterministic case", reals);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < reals.size(); ++i) {
    const std::string where = "realizations[" + std::to_string(i) + "]";
    if (!reals[i].is_object()) throw field_error(path, where, "an object", reals[i]);
    const json folder = reals[i].contains("folder") ? reals[i].at("folder") : json();
    if (!folder.is_string() || folder.get<std::string>().empty() ||
        folder.get<std::string>().find('/') != std::string::npos || seen.count(folder.get<std::string>()))
      throw field_error(path, where + ".folder", "a unique folder name without '/'", folder);
    seen.insert(folder.get<std::string>());
    m.folders.push_back(folder.get<std::string>());
  }

  const auto& tables = need("tables");
  if (!tables.is_array() || tables.empty()) throw field_error(path, "tables", "a non-empty list", tables);
  const std::string tol_name = m.kind == "ensemble" ? "k" : "tol";
  const std::string other = m.kind == "ensemble" ? "tol" : "k";
  std::set<std::string> files;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const std::string where = "tables[" + std::to_string(i) + "]";
    const auto& t = tables[i];
    if (!t.is_object()) throw field_error(path, where, "an object", t);
    TableSpec spec;
    const json file = t.contains("file") ? t.at("file") : json();
    const std::string f = file.is_string() ? file.get<std::string>() : "";
    if (f.size() < 5 || f.compare(f.size() - 4, 4, ".csv") != 0 || f.find('/') != std::string::npos)
      throw field_error(path, where + ".file", "a CSV file name of the run folder (e.g. timeseries.csv)", file);
    if (files.count(f)) throw field_error(path, "tables", "each file once");
    files.insert(f);
    spec.file = f;
    const json key = t.contains("key") ? t.at("key") : json();
    if (key.is_string() && !key.get<std::string>().empty()) {
      spec.keys.push_back(key.get<std::string>());
    } else if (key.is_array() && !key.empty()) {
      for (const auto& k : key) {
        if (!k.is_string() || k.get<std::string>().empty())
          throw field_error(path, where + ".key", "a column name or a list of column names", key);
        spec.keys.push_back(k.get<std::string>());
      }
    } else {
      throw field_error(path, where + ".key", "a column name or a list of column names", key);
    }
    const json cols = t.contains("columns") ? t.at("columns") : json();
    if (!cols.is_object() || cols.empty())
      throw field_error(path, where + ".columns", "a non-empty object {column: {tolerance}}", cols);
    for (const auto& [cname, c] : cols.items()) {
      const std::string cw = where + ".columns." + cname;
      if (std::find(spec.keys.begin(), spec.keys.end(), cname) != spec.keys.end())
        throw field_error(path, cw, "a column that is not a key column");
      if (!c.is_object())
        throw field_error(path, cw, "an object {\"" + tol_name + "\", \"floor\", \"reason\"}", c);
      for (const auto& [k, v] : c.items()) {
        (void)v;
        if (k != tol_name && k != "floor" && k != "reason") {
          std::string hint;
          if (k == other)
            hint = " ('" + other + "' is for " + (other == "tol" ? "deterministic" : "ensemble") + " cases)";
          throw field_error(path, cw + "." + k, "one of " + tol_name + ", floor, reason (unknown field)" + hint);
        }
      }
      ColumnSpec cs;
      cs.name = cname;
      if (!c.contains(tol_name))
        throw field_error(path, cw + "." + tol_name, "a finite number >= 0 (the field is required)");
      if (!finite_number(c.at(tol_name)) || c.at(tol_name).get<double>() < 0)
        throw field_error(path, cw + "." + tol_name, "a finite number >= 0 (the field is required)", c.at(tol_name));
      cs.tol = c.at(tol_name).get<double>();
      if (!c.contains("floor")) throw field_error(path, cw + ".floor", "a finite number > 0 (the field is required)");
      if (!finite_number(c.at("floor")) || !(c.at("floor").get<double>() > 0))
        throw field_error(path, cw + ".floor", "a finite number > 0 (the field is required)", c.at("floor"));
      cs.floor = c.at("floor").get<double>();
      const std::string reason_what = "a non-empty string: why the tolerance has its value";
      if (!c.contains("reason")) throw field_error(path, cw + ".reason", reason_what);
      if (!c.at("reason").is_string() || trim(c.at("reason").get<std::string>()).empty())
        throw field_error(path, cw + ".reason", reason_what, c.at("reason"));
      cs.reason = c.at("reason").get<std::string>();
      spec.columns.push_back(cs);
    }
    m.tables.push_back(spec);
  }
  return m;
}

Manifest load_manifest(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ManifestError(path + ": missing");
  nlohmann::ordered_json raw;  // ordered: columns are compared in the manifest's order
  try {
    in >> raw;
  } catch (const nlohmann::json::exception& e) {
    throw ManifestError(path + ": not valid JSON: " + e.what());
  }
  return parse_manifest(path, raw);
}

// --- A case ---------------------------------------------------------------------------------------

bool CaseResult::passed() const {
  return problems.empty() &&
         std::all_of(columns.begin(), columns.end(), [](const ColumnResult& c) { return c.passed; });
}

namespace {

std::vector<std::vector<double>> keys_of(const Table& t, const std::vector<std::string>& names) {
  std::vector<std::vector<double>> cols;
  for (const auto& n : names) cols.push_back(t.column(n));
  std::vector<std::vector<double>> rows(t.rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (const auto& c : cols) rows[i].push_back(c[i]);
  return rows;
}

std::string key_g17(const std::vector<double>& k) {
  std::vector<std::string> parts;
  for (double x : k) parts.push_back(g17(x));
  return join(parts, "/");
}

}  // namespace

CaseResult compare_case(const Manifest& m, const std::string& golden_dir, const std::string& new_dir, double scale) {
  CaseResult res;
  res.case_name = m.case_name;
  res.kind = m.kind;
  res.scale = scale;
  for (const auto& spec : m.tables) {
    std::vector<Table> gold, fresh;
    bool ok = true;
    for (const auto& folder : m.folders) {
      for (int side = 0; side < 2; ++side) {
        const std::string root = side == 0 ? golden_dir : new_dir;
        const std::string p = root + "/" + folder + "/" + spec.file;
        try {
          Table t = read_table(p);
          for (const auto& k : spec.keys) t.column(k);
          for (const auto& c : spec.columns) t.column(c.name);
          (side == 0 ? gold : fresh).push_back(std::move(t));
        } catch (const TableError& e) {
          std::string msg = std::string(side == 0 ? "golden" : "new") + " file: " + e.what();
          if (side == 0)
            msg += " (golden data is never made silently: regenerate on purpose with regression/run --update " +
                   m.case_name + ")";
          res.problems.push_back(msg);
          ok = false;
        }
      }
    }
    if (!ok) continue;
    std::vector<std::vector<std::vector<double>>> gold_keys, new_keys;
    for (const auto& t : gold) gold_keys.push_back(keys_of(t, spec.keys));
    for (const auto& t : fresh) new_keys.push_back(keys_of(t, spec.keys));
    const auto& ref = gold_keys.front();
    std::vector<std::pair<const Table*, const std::vector<std::vector<double>>*>> all;
    for (std::size_t i = 0; i < gold.size(); ++i) all.emplace_back(&gold[i], &gold_keys[i]);
    for (std::size_t i = 0; i < fresh.size(); ++i) all.emplace_back(&fresh[i], &new_keys[i]);
    for (const auto& [t, keys] : all) {
      if (keys->size() != ref.size()) {
        res.problems.push_back(t->path + ": " + std::to_string(keys->size()) + " rows, the golden " +
                               gold.front().path + " has " + std::to_string(ref.size()));
        ok = false;
        continue;
      }
      const long i = first_key_mismatch(*keys, ref);
      if (i >= 0) {
        const auto u = static_cast<std::size_t>(i);
        res.problems.push_back(t->path + ": key " + join(spec.keys, "/") + " differs at row " + std::to_string(i + 1) +
                               ": " + key_g17((*keys)[u]) + " against " + key_g17(ref[u]) + " in " +
                               gold.front().path + " (the rows must be recorded at the same times)");
        ok = false;
      }
    }
    if (!ok) continue;
    for (const auto& col : spec.columns) {
      if (m.kind == "deterministic") {
        res.columns.push_back(compare_deterministic(col.name, fresh.front().column(col.name),
                                                    gold.front().column(col.name), col.tol, col.floor, scale, ref,
                                                    spec.file));
      } else {
        std::vector<std::vector<double>> a, b;
        for (const auto& t : fresh) a.push_back(t.column(col.name));
        for (const auto& t : gold) b.push_back(t.column(col.name));
        res.columns.push_back(compare_ensemble(col.name, a, b, col.tol, col.floor, scale, ref, spec.file));
      }
    }
  }
  return res;
}

std::string format_report(const CaseResult& r, const Manifest& m) {
  std::map<std::string, std::vector<std::string>> key_names;
  for (const auto& t : m.tables) key_names[t.file] = t.keys;
  std::string out;
  char buf[512];
  std::snprintf(buf, sizeof buf, "case %s (%s, tol-scale %g)\n", r.case_name.c_str(), r.kind.c_str(), r.scale);
  out += buf;
  if (!r.columns.empty()) {
    std::snprintf(buf, sizeof buf, "  %-15s %-22s %5s %4s %9s %9s %9s  %-24s %12s %12s %8s %8s  result\n", "table",
                  "column", "n", "fail", "mean", "std", "worst", "at", "new", "golden", "tol", "floor");
    out += buf;
  }
  for (const auto& c : r.columns) {
    std::string where = "-";
    if (c.worst_row >= 0) {
      std::vector<std::string> parts;
      const auto& names = key_names[c.table];
      for (std::size_t i = 0; i < c.worst_key.size(); ++i)
        parts.push_back(i < names.size() ? names[i] + "=" + key_text(c.worst_key[i]) : key_text(c.worst_key[i]));
      where = join(parts, ",") + " (row " + std::to_string(c.worst_row + 1) + ")";
    }
    std::snprintf(buf, sizeof buf, "  %-15s %-22s %5zu %4zu %9s %9s %9s  %-24s %12s %12s %8s %8s  %s\n",
                  c.table.c_str(), c.column.c_str(), c.n, c.failures, g3(c.mean).c_str(), g3(c.std).c_str(),
                  g3(c.max).c_str(), where.c_str(), g3(c.worst_new).c_str(), g3(c.worst_golden).c_str(),
                  g3(c.tol).c_str(), g3(c.floor).c_str(), c.passed ? "pass" : "FAIL");
    out += buf;
  }
  for (const auto& p : r.problems) out += "  problem: " + p + "\n";
  const ColumnResult* worst = nullptr;
  double worst_ratio = -1;
  for (const auto& c : r.columns) {
    const double allow = c.tol * c.scale;
    const double ratio = c.max == 0.0 ? 0.0 : (allow == 0.0 ? kInf : c.max / allow);
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = &c;
    }
  }
  const char* verdict = r.passed() ? "PASS" : "FAIL";
  std::vector<std::string> parts;
  if (!r.problems.empty()) parts.push_back(std::to_string(r.problems.size()) + " problem(s)");
  if (worst)
    parts.push_back("worst: " + worst->table + " " + worst->column + " err " + g3(worst->max) + ", allowed " +
                    g3(worst->tol * worst->scale));
  out += "case " + r.case_name + ": " + verdict + (parts.empty() ? "" : " (" + join(parts, "; ") + ")") + "\n";
  return out;
}

nlohmann::json json_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

double from_json_number(const nlohmann::json& x) {
  if (x.is_string()) {
    const auto s = x.get<std::string>();
    if (s == "nan") return kNaN;
    if (s == "inf") return kInf;
    if (s == "-inf") return -kInf;
    throw std::invalid_argument("expected a number or one of nan, inf, -inf, got '" + s + "'");
  }
  if (!x.is_number()) throw std::invalid_argument("expected a number, got " + x.dump());
  return x.get<double>();
}

nlohmann::json to_json(const CaseResult& r) {
  nlohmann::json cols = nlohmann::json::array();
  for (const auto& c : r.columns) {
    nlohmann::json key = nlohmann::json::array();
    for (double k : c.worst_key) key.push_back(json_number(k));
    cols.push_back({{"table", c.table},
                    {"column", c.column},
                    {"kind", c.kind},
                    {"tol", json_number(c.tol)},
                    {"floor", json_number(c.floor)},
                    {"scale", json_number(c.scale)},
                    {"n", c.n},
                    {"failures", c.failures},
                    {"mean", json_number(c.mean)},
                    {"std", json_number(c.std)},
                    {"max", json_number(c.max)},
                    {"worst_row", c.worst_row},
                    {"worst_key", key},
                    {"worst_new", json_number(c.worst_new)},
                    {"worst_golden", json_number(c.worst_golden)},
                    {"worst_se", json_number(c.kind == "ensemble" ? c.worst_se : kNaN)},
                    {"passed", c.passed}});
  }
  return {{"case", r.case_name}, {"kind", r.kind},         {"scale", json_number(r.scale)},
          {"passed", r.passed()}, {"problems", r.problems}, {"columns", cols}};
}

double tol_scale_from(const char* arg, const char* env_value) {
  const char* text = arg ? arg : env_value;
  const std::string where = arg ? "--tol-scale" : "RATCHET_TOL_SCALE";
  if (!text || !*text) return 1.0;
  double v;
  const std::string t(text);
  if (!parse_cell(t, v) || trim(t).empty() || !std::isfinite(v) || v < 0)
    throw std::invalid_argument(where + ": expected a number >= 0, got '" + t + "'");
  return v;
}

}  // namespace ratchet::regression

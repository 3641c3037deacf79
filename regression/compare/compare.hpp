// The golden-curve comparison rule of ratchet, in C++ (docs/regression.md).
//
// The same rule is implemented in Python in scripts/regression/compare.py; both are
// checked against the shared test vectors regression/compare_vectors.json
// (compare_test.cpp here, scripts/tests/test_regression_compare.py there). Keep the two
// in step: the same formulas, the same order of floating-point operations (plain
// left-to-right loops), the same handling of non-finite values.
//
// The rule (a: new value, b: golden value, tol: the column's tol, or k for an ensemble,
// scale: the global tolerance scale, 1 by default):
//   deterministic  err = |a - b| / max(|b|, floor)
//                  (0 when a == b or both NaN; inf when only one is finite or they are
//                  different infinities)
//   ensemble       per row: m = mean over the realizations, s = sample standard
//                  deviation (n - 1; 0 when n == 1), se = sqrt(s_a^2/n_a + s_b^2/n_b),
//                  err = |m_a - m_b| / max(se, floor)
//                  (0 when every value of both sides is NaN or all are the same
//                  infinity; inf when some other value is not finite)
//   a row passes when err <= tol * scale; scale 0 shows the real residuals (only
//   err == 0 passes).
// Per column: n, failures, the mean and the population standard deviation of err over
// the rows (both inf when some err is inf), the worst err and the first row holding it.
// Key columns (recorded times, cycle numbers, run ids) must agree row by row to
// kKeyTol (err with floor kKeyFloor), not scaled.
#pragma once

#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ratchet::regression {

inline constexpr double kKeyTol = 1e-12;
inline constexpr double kKeyFloor = 1.0;

// --- The rule --------------------------------------------------------------------

// Deterministic error of the new value a against the golden value b.
double value_error(double a, double b, double floor);

struct EnsembleValue {
  double err;
  double mean_new;
  double mean_golden;
  double se;
};
// Ensemble error of one row: the new realizations' values against the golden ones'.
EnsembleValue ensemble_error(const std::vector<double>& new_values, const std::vector<double>& golden_values,
                             double floor);

// The pass test of one row: err <= tol * scale.
inline bool within(double err, double tol, double scale) { return err <= tol * scale; }

struct ColumnResult {
  std::string table;
  std::string column;
  std::string kind;  // "deterministic" or "ensemble"
  double tol = 0, floor = 0, scale = 1;
  std::size_t n = 0;
  std::size_t failures = 0;
  double mean = 0, std = 0, max = 0;
  long worst_row = -1;              // 0-based data row; -1 when there is no row
  std::vector<double> worst_key;    // key values of the worst row
  double worst_new = 0, worst_golden = 0;  // the values (ensemble: the means) there
  double worst_se = 0;              // ensemble only
  bool passed = true;
};

// Pointwise comparison of one column whose rows are already aligned by their keys.
// keys: one vector of key values per row (may be empty).
ColumnResult compare_deterministic(const std::string& column, const std::vector<double>& new_values,
                                   const std::vector<double>& golden_values, double tol, double floor,
                                   double scale, const std::vector<std::vector<double>>& keys = {},
                                   const std::string& table = "");

// Row-by-row comparison of the realizations' means: new_values[r][i] is realization r, row i.
ColumnResult compare_ensemble(const std::string& column, const std::vector<std::vector<double>>& new_values,
                              const std::vector<std::vector<double>>& golden_values, double k, double floor,
                              double scale, const std::vector<std::vector<double>>& keys = {},
                              const std::string& table = "");

// First row whose keys differ by more than kKeyTol (err with floor kKeyFloor), or -1.
long first_key_mismatch(const std::vector<std::vector<double>>& new_keys,
                        const std::vector<std::vector<double>>& golden_keys);

// --- CSV tables --------------------------------------------------------------------

// A CSV that cannot be compared (missing, unreadable, missing column, bad cell).
struct TableError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A CSV cell as a double: numbers including nan, inf, -inf; an empty cell is NaN.
// Returns false when the cell is not a number.
bool parse_cell(const std::string& text, double& out);

struct Table {
  std::string path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  // The named column as numbers; TableError (naming file, row and column) otherwise.
  std::vector<double> column(const std::string& name) const;
};
Table read_table(const std::string& path);

// --- Manifest ------------------------------------------------------------------------

// A malformed manifest: the message names the file and the field.
struct ManifestError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ColumnSpec {
  std::string name;
  double tol = 0;  // "tol" (deterministic) or "k" (ensemble)
  double floor = 0;
  std::string reason;
};
struct TableSpec {
  std::string file;
  std::vector<std::string> keys;
  std::vector<ColumnSpec> columns;
};
struct Manifest {
  std::string path;
  std::string case_name;
  std::string kind;
  std::vector<std::string> folders;  // one run folder per realization, in order
  std::vector<TableSpec> tables;
};
// Reads and checks the fields the comparison needs (the driver checks the rest).
Manifest load_manifest(const std::string& path);
Manifest parse_manifest(const std::string& path, const nlohmann::ordered_json& raw);

// --- A case ----------------------------------------------------------------------------

struct CaseResult {
  std::string case_name;
  std::string kind;
  double scale = 1;
  std::vector<ColumnResult> columns;
  std::vector<std::string> problems;  // structural failures
  bool passed() const;
};

// Compares the run folders under new_dir (named as the manifest's realizations) with the
// golden files under golden_dir.
CaseResult compare_case(const Manifest& m, const std::string& golden_dir, const std::string& new_dir,
                        double scale);

// The human report (the same layout as scripts/regression/compare.py's format_report).
std::string format_report(const CaseResult& r, const Manifest& m);

// Machine-readable result; non-finite numbers as the strings "nan", "inf", "-inf".
nlohmann::json to_json(const CaseResult& r);
nlohmann::json json_number(double x);
// Inverse of json_number (test vectors); throws std::invalid_argument.
double from_json_number(const nlohmann::json& x);

// --tol-scale text if given (non-null), else $RATCHET_TOL_SCALE, else 1; throws
// std::invalid_argument naming the source when it is not a number >= 0.
double tol_scale_from(const char* arg, const char* env_value);

}  // namespace ratchet::regression

#pragma once
// Records the physics checks of a validation case for the validation report
// (scripts/report.py; the file format is in scripts/README.md).
//
// When the environment variable RATCHET_CHECKS_DIR is set, every check appends one
// JSON line to $RATCHET_CHECKS_DIR/<program>-<pid>.jsonl:
//   {"case":..., "check":..., "measured":..., "expected":..., "tolerance":...,
//    "reason":..., "passed":...}
// measured is written at full round-trip precision; a non-finite measured value
// (NaN, +-Inf) is written as null and the check fails. Without the variable nothing
// is written. A relative RATCHET_CHECKS_DIR is taken from the test's working folder
// (CTest runs each test in its build sub-folder): scripts/validate passes an absolute one.
// A set but unwritable folder throws std::runtime_error: a check that cannot be
// recorded must not vanish from the report silently.
//
// Each function returns whether the check passed, for use in a GoogleTest assertion:
//   EXPECT_TRUE(check_rel("free_fall", "z(t=2)", z, -2.0, 1e-9, "exact integrator"));

#include <string>

namespace ratchet::validation {

// Records one check and returns `passed` (false whatever `passed` says when
// `measured` is not finite). `expected` and `tolerance` are free text for the report.
bool record(const std::string& case_name, const std::string& check, double measured,
            const std::string& expected, const std::string& tolerance, bool passed,
            const std::string& reason = "");

// Passes when |measured - expected| <= abs_tol.
bool check_near(const std::string& case_name, const std::string& check, double measured,
                double expected, double abs_tol, const std::string& reason);

// Passes when |measured - expected| <= rel_tol * |expected|.
bool check_rel(const std::string& case_name, const std::string& check, double measured,
               double expected, double rel_tol, const std::string& reason);

// Passes when measured <= bound.
bool check_le(const std::string& case_name, const std::string& check, double measured,
              double bound, const std::string& reason);

// Shortest decimal text that reads back to exactly `value` ("0.1", "1e-06", "nan").
std::string format_number(double value);

}  // namespace ratchet::validation

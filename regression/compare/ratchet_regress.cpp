// ratchet_regress: compares run folders with a golden case, by the C++ implementation of
// the comparison rule (compare.hpp, docs/regression.md).
//
//   ratchet_regress compare CASE_DIR RUN_DIR [--tol-scale S] [--json FILE]
//   ratchet_regress check CASE_DIR ...        checks manifests only
//
// CASE_DIR is golden/<case> (manifest.json and the golden CSVs in one folder per
// realization); RUN_DIR holds the new runs in folders of the same names (what
// regression/run writes). Exit status: 0 pass, 1 fail, 2 usage error or malformed manifest.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "compare/compare.hpp"

namespace {

const char* kUsage =
    "usage:\n"
    "  ratchet_regress compare CASE_DIR RUN_DIR [--tol-scale S] [--json FILE]\n"
    "      compare the runs in RUN_DIR/<realization folder>/ with the golden case CASE_DIR\n"
    "      (tolerance scale: --tol-scale, else $RATCHET_TOL_SCALE, else 1; 0 shows the residuals)\n"
    "  ratchet_regress check CASE_DIR ...\n"
    "      check the manifests only\n"
    "Exit status: 0 pass, 1 fail, 2 usage error or malformed manifest. See docs/regression.md.\n";

int usage(const std::string& msg) {
  std::cerr << "ratchet_regress: " << msg << "\n" << kUsage;
  return 2;
}

// Writes text to path through path.partial and a rename.
bool write_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".partial";
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) return false;
    out << text;
    out.flush();
    if (!out) return false;
  }
  return std::rename(tmp.c_str(), path.c_str()) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  namespace rr = ratchet::regression;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return usage("no command");
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (args[0] == "check") {
    if (args.size() < 2) return usage("check needs at least one CASE_DIR");
    int rc = 0;
    for (std::size_t i = 1; i < args.size(); ++i) {
      try {
        const auto m = rr::load_manifest(args[i] + "/manifest.json");
        std::cout << m.case_name << ": manifest ok (" << m.kind << ", " << m.folders.size() << " realization(s), "
                  << m.tables.size() << " table(s))\n";
      } catch (const rr::ManifestError& e) {
        std::cerr << "ratchet_regress: error: " << e.what() << "\n";
        rc = 2;
      }
    }
    return rc;
  }
  if (args[0] != "compare") return usage("unknown command '" + args[0] + "'");

  std::vector<std::string> positional;
  std::string scale_text;
  bool have_scale = false;
  std::string json_path;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--tol-scale" || a == "--json") {
      if (i + 1 >= args.size()) return usage(a + " needs a value");
      if (a == "--tol-scale") {
        scale_text = args[i + 1];
        have_scale = true;
      } else {
        json_path = args[i + 1];
      }
      ++i;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option '" + a + "'");
    } else {
      positional.push_back(a);
    }
  }
  if (positional.size() != 2) return usage("compare needs CASE_DIR and RUN_DIR");
  double scale;
  try {
    scale = rr::tol_scale_from(have_scale ? scale_text.c_str() : nullptr, std::getenv("RATCHET_TOL_SCALE"));
  } catch (const std::invalid_argument& e) {
    return usage(e.what());
  }
  rr::Manifest m;
  try {
    m = rr::load_manifest(positional[0] + "/manifest.json");
  } catch (const rr::ManifestError& e) {
    std::cerr << "ratchet_regress: error: " << e.what() << "\n";
    return 2;
  }
  const rr::CaseResult r = rr::compare_case(m, positional[0], positional[1], scale);
  std::cout << rr::format_report(r, m);
  if (!json_path.empty() && !write_atomic(json_path, rr::to_json(r).dump(1) + "\n")) {
    std::cerr << "ratchet_regress: error: cannot write " << json_path << "\n";
    return 2;
  }
  return r.passed() ? 0 : 1;
}

// The .pvd index: one DataSet per entry in order, times that read back to the same
// double, file names escaped for XML, and nothing written for bad input.
#include "ratchet/observe/pvd_writer.hpp"

#include <gtest/gtest.h>

#include "support/test_files.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ratchet {
namespace {
using test::read_text;

namespace fs = std::filesystem;

fs::path temp_dir() { return test::fresh_dir("ratchet_pvd"); }

TEST(PvdWriter, ListsEveryEntryWithItsExactTime) {
  const fs::path d = temp_dir();
  const double t1 = 0.1 + 0.2;  // 0.30000000000000004: needs all 17 digits
  write_pvd((d / "a.pvd").string(), {{0.0, "particles_step00000000.vtp"}, {t1, "particles_step00000100.vtp"},
                                     {1e6 / 3.0, "p&<\">.vtp"}});
  EXPECT_FALSE(fs::exists(d / "a.pvd.partial"));
  const std::string text = read_text(d / "a.pvd");
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\"", 0), 0u);
  EXPECT_NE(text.find("<Collection>\n"), std::string::npos);
  EXPECT_NE(text.find("</Collection>\n</VTKFile>\n"), std::string::npos);
  static const std::regex dataset(R"re(<DataSet timestep="([^"]*)" group="" part="0" file="([^"]*)"/>)re");
  std::vector<double> times;
  std::vector<std::string> files;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset); it != std::sregex_iterator(); ++it) {
    times.push_back(std::stod((*it)[1]));
    files.push_back((*it)[2]);
  }
  EXPECT_EQ(times, (std::vector<double>{0.0, t1, 1e6 / 3.0}));  // to the last bit
  EXPECT_EQ(files, (std::vector<std::string>{"particles_step00000000.vtp", "particles_step00000100.vtp",
                                             "p&amp;&lt;&quot;&gt;.vtp"}));
  // Rewritten whole: a shorter list replaces the longer one.
  write_pvd((d / "a.pvd").string(), {});
  EXPECT_EQ(read_text(d / "a.pvd").find("<DataSet"), std::string::npos);
  fs::remove_all(d);
}

TEST(PvdWriter, BadInputWritesNothing) {
  const fs::path d = temp_dir();
  const std::string path = (d / "bad.pvd").string();
  EXPECT_THROW(write_pvd(path, {{0.0, "a.vtp"}, {std::nan(""), "b.vtp"}}), std::invalid_argument);
  EXPECT_THROW(write_pvd(path, {{0.0, ""}}), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(write_pvd((d / "no-such-dir" / "x.pvd").string(), {}), std::runtime_error);
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet

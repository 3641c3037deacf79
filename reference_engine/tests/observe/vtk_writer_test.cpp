#include "ratchet/observe/vtk_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ratchet {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() /
                     ("ratchet_vtk_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// A minimal legacy-VTK POLYDATA reader: checks that every section's header count
// matches the lines that follow it, and returns the section headers it met.
struct Parsed {
  std::size_t points = 0, vertices = 0, polygons = 0, lines = 0, cell_data = 0, point_data = 0;
  std::vector<std::string> sections;
  std::vector<std::vector<long>> polygon_cells, line_cells;
};

std::vector<double> numbers(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

Parsed parse(const std::vector<std::string>& l) {
  Parsed p;
  EXPECT_GE(l.size(), 5u);
  EXPECT_EQ(l[0], "# vtk DataFile Version 3.0");
  EXPECT_FALSE(l[1].empty());
  EXPECT_EQ(l[2], "ASCII");
  EXPECT_EQ(l[3], "DATASET POLYDATA");
  std::size_t i = 4, cells = 0;
  auto read_cells = [&](std::size_t n, std::size_t size, std::vector<std::vector<long>>* out) {
    std::size_t total = 0;
    for (std::size_t c = 0; c < n; ++c, ++i) {
      const std::vector<double> v = numbers(l.at(i));
      EXPECT_FALSE(v.empty());
      EXPECT_EQ(v.size(), static_cast<std::size_t>(v[0]) + 1) << l[i];
      for (std::size_t k = 1; k < v.size(); ++k) EXPECT_LT(v[k], static_cast<double>(p.points)) << l[i];
      total += v.size();
      if (out) out->emplace_back(v.begin() + 1, v.end());
    }
    EXPECT_EQ(total, size);
  };
  std::size_t data_count = 0;  // values per array in the current CELL_DATA / POINT_DATA block
  while (i < l.size()) {
    std::istringstream in(l[i++]);
    std::string key;
    in >> key;
    p.sections.push_back(key);
    if (key == "POINTS") {
      std::string type;
      in >> p.points >> type;
      EXPECT_EQ(type, "double");
      for (std::size_t k = 0; k < p.points; ++k, ++i) EXPECT_EQ(numbers(l.at(i)).size(), 3u) << l[i];
    } else if (key == "VERTICES" || key == "POLYGONS" || key == "LINES") {
      std::size_t n = 0, size = 0;
      in >> n >> size;
      (key == "VERTICES" ? p.vertices : key == "POLYGONS" ? p.polygons : p.lines) = n;
      cells += n;
      read_cells(n, size, key == "POLYGONS" ? &p.polygon_cells : key == "LINES" ? &p.line_cells : nullptr);
    } else if (key == "CELL_DATA" || key == "POINT_DATA") {
      in >> data_count;
      (key == "CELL_DATA" ? p.cell_data : p.point_data) = data_count;
      EXPECT_EQ(data_count, key == "CELL_DATA" ? cells : p.points);
    } else if (key == "SCALARS") {
      EXPECT_EQ(l.at(i++), "LOOKUP_TABLE default");
      for (std::size_t k = 0; k < data_count; ++k, ++i) EXPECT_EQ(numbers(l.at(i)).size(), 1u) << l[i];
    } else if (key == "FIELD") {
      std::string name;
      std::size_t arrays = 0;
      in >> name >> arrays;
      for (std::size_t a = 0; a < arrays; ++a) {
        std::istringstream h(l.at(i++));
        std::string array, type;
        std::size_t comps = 0, tuples = 0;
        h >> array >> comps >> tuples >> type;
        EXPECT_EQ(tuples, data_count) << array;
        for (std::size_t k = 0; k < tuples; ++k, ++i) EXPECT_EQ(numbers(l.at(i)).size(), comps) << l[i];
      }
    } else if (key == "VECTORS") {
      for (std::size_t k = 0; k < data_count; ++k, ++i) EXPECT_EQ(numbers(l.at(i)).size(), 3u) << l[i];
    } else {
      ADD_FAILURE() << "unexpected line " << i << ": " << l[i - 1];
      break;
    }
  }
  return p;
}

VtkBody cube(int id, const Vec3& lo) {
  VtkBody b;
  b.id = id;
  b.velocity = Vec3(0.1 * id, 0.0, -1.0);
  for (int i = 0; i < 8; ++i) b.vertices.push_back(lo + Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  b.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return b;
}

TEST(VtkWriter, ParticlesParseWithConsistentCounts) {
  const fs::path d = temp_dir();
  const fs::path path = d / "particles.vtk";
  VtkBody sphere;
  sphere.id = 7;
  sphere.vertices = {Vec3(5, 5, 5)};
  sphere.sphere_radius = 0.75;
  write_particles_vtk(path.string(), {cube(0, Vec3::Zero()), sphere, cube(1, Vec3(3, 0, 0))});
  EXPECT_FALSE(fs::exists(path.string() + ".partial"));
  const std::vector<std::string> lines = read_lines(path);
  const Parsed p = parse(lines);
  EXPECT_EQ(p.points, 17u);
  EXPECT_EQ(p.vertices, 1u);
  EXPECT_EQ(p.polygons, 12u);
  EXPECT_EQ(p.cell_data, 13u);
  EXPECT_EQ(p.point_data, 17u);
  // The second cube's faces index its own points, after the first cube (0..7) and the
  // sphere's centre (8).
  ASSERT_EQ(p.polygon_cells.size(), 12u);
  EXPECT_EQ(p.polygon_cells[6], (std::vector<long>{9, 11, 12, 10}));
  // Cell data order: the sphere's cell first, then 6 faces of body 0, 6 of body 1.
  const auto body_id = std::find(lines.begin(), lines.end(), "SCALARS body_id int 1");
  ASSERT_NE(body_id, lines.end());
  EXPECT_EQ(*(body_id + 2), "7");
  EXPECT_EQ(*(body_id + 3), "0");
  EXPECT_EQ(*(body_id + 14), "1");
  const auto radius = std::find(lines.begin(), lines.end(), "SCALARS radius double 1");
  ASSERT_NE(radius, lines.end());
  EXPECT_EQ(*(radius + 2 + 8), "0.75");
  EXPECT_EQ(*(radius + 2), "0");
  fs::remove_all(d);
}

TEST(VtkWriter, ContactNetworkParsesAsLines) {
  const fs::path d = temp_dir();
  const fs::path path = d / "contacts.vtk";
  const std::vector<VtkContact> c = {
      {Vec3(0, 0, 0), Vec3(1, 0, 0), 2.5, 0, 1},
      {Vec3(1, 0, 0), Vec3(1, 1, 0), 0.125, 1, 2},
      {Vec3(1, 1, 0), Vec3(1, 1, -0.5), 10.0, 2, -1},  // wall contact: centre to contact point
  };
  write_contact_network_vtk(path.string(), c);
  EXPECT_FALSE(fs::exists(path.string() + ".partial"));
  const std::vector<std::string> lines = read_lines(path);
  const Parsed p = parse(lines);
  EXPECT_EQ(p.points, 6u);
  EXPECT_EQ(p.lines, 3u);
  EXPECT_EQ(p.cell_data, 3u);
  ASSERT_EQ(p.line_cells.size(), 3u);
  EXPECT_EQ(p.line_cells[2], (std::vector<long>{4, 5}));
  const auto force = std::find(lines.begin(), lines.end(), "SCALARS normal_force double 1");
  ASSERT_NE(force, lines.end());
  EXPECT_EQ(*(force + 2), "2.5");
  EXPECT_EQ(*(force + 3), "0.125");
  EXPECT_EQ(*(force + 4), "10");
  EXPECT_NE(std::find(lines.begin(), lines.end(), "FIELD FieldData 2"), lines.end());
  const auto body_b = std::find(lines.begin(), lines.end(), "body_b 1 3 int");
  ASSERT_NE(body_b, lines.end());
  EXPECT_EQ(*(body_b + 1), "1");
  EXPECT_EQ(*(body_b + 3), "-1");
  fs::remove_all(d);
}

TEST(VtkWriter, EmptyInputStillGivesAValidFile) {
  const fs::path d = temp_dir();
  write_contact_network_vtk((d / "none.vtk").string(), {});
  write_particles_vtk((d / "nobody.vtk").string(), {});
  const Parsed a = parse(read_lines(d / "none.vtk"));
  const Parsed b = parse(read_lines(d / "nobody.vtk"));
  EXPECT_EQ(a.points, 0u);
  EXPECT_EQ(b.points, 0u);
  EXPECT_EQ(a.sections, (std::vector<std::string>{"POINTS"}));
  fs::remove_all(d);
}

TEST(VtkWriter, InvalidInputLeavesNoFile) {
  const fs::path d = temp_dir();
  const std::string path = (d / "bad.vtk").string();
  VtkBody bad = cube(0, Vec3::Zero());
  bad.faces[2][1] = 8;  // out of range
  EXPECT_THROW(write_particles_vtk(path, {bad}), std::invalid_argument);
  VtkBody flat = cube(0, Vec3::Zero());
  flat.faces[0] = {0, 1};
  EXPECT_THROW(write_particles_vtk(path, {flat}), std::invalid_argument);
  EXPECT_THROW(write_contact_network_vtk(path, {{Vec3(std::nan(""), 0, 0), Vec3::Zero(), 1.0, 0, 1}}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(write_contact_network_vtk((d / "no-such-dir" / "x.vtk").string(), {}), std::runtime_error);
  fs::remove_all(d);
}

TEST(VtkWriter, TitleIsOneLine) {
  const fs::path d = temp_dir();
  write_contact_network_vtk((d / "t.vtk").string(), {}, "cycle 3\nend of cooling");
  const std::vector<std::string> l = read_lines(d / "t.vtk");
  ASSERT_GE(l.size(), 4u);
  EXPECT_EQ(l[1], "cycle 3 end of cooling");
  EXPECT_EQ(l[2], "ASCII");
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet

// The VTK XML PolyData writers: counts that agree with each other (points, cells,
// tuples of every array), cell order and offsets, the arrays' values, the time field,
// and no file at all for bad input. scripts/tests/test_vtk_output.py reads real runs'
// files back with VTK's own reader.
#include "ratchet/observe/vtk_writer.hpp"

#include <gtest/gtest.h>

#include "support/test_files.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ratchet {
namespace {
using test::read_text;

namespace fs = std::filesystem;

fs::path temp_dir() { return test::fresh_dir("ratchet_vtk"); }

// A minimal reader of the XML this writer produces: every element's attributes, and
// each DataArray's numbers under its section (FieldData, PointData, CellData, Points,
// Verts, Polys).
struct Array {
  std::map<std::string, std::string> attr;
  std::vector<double> values;
  int components() const { return attr.count("NumberOfComponents") ? std::stoi(attr.at("NumberOfComponents")) : 1; }
};
struct Vtp {
  std::map<std::string, std::string> file, piece;
  std::map<std::string, std::map<std::string, Array>> sections;
  std::size_t count(const char* key) const { return std::stoul(piece.at(key)); }
  const Array& at(const std::string& section, const std::string& name) const { return sections.at(section).at(name); }
};

std::map<std::string, std::string> attributes(const std::string& text) {
  std::map<std::string, std::string> out;
  static const std::regex attr(R"re((\w+)="([^"]*)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), attr); it != std::sregex_iterator(); ++it)
    out[(*it)[1]] = (*it)[2];
  return out;
}

Vtp parse(const std::string& xml) {
  Vtp v;
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\"?>\n", 0), 0u);
  static const std::regex tag(R"re(<(/?)(\w+)([^>]*?)(/?)>)re");
  std::string section;
  Array* open = nullptr;
  std::size_t text_from = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    const bool closing = m[1] == "/";
    const std::string name = m[2];
    if (name == "DataArray" && closing) {
      std::istringstream in(xml.substr(text_from, static_cast<std::size_t>(m.position()) - text_from));
      for (std::string word; in >> word;) open->values.push_back(std::stod(word));
      open = nullptr;
    } else if (name == "DataArray") {
      Array a;
      a.attr = attributes(m[3]);
      EXPECT_EQ(a.attr["format"], "ascii");
      Array& slot = v.sections[section][a.attr["Name"]];
      EXPECT_TRUE(slot.attr.empty()) << "two arrays " << a.attr["Name"] << " in " << section;
      slot = a;
      open = &slot;
      text_from = static_cast<std::size_t>(m.position() + m.length());
    } else if (name == "VTKFile" && !closing) {
      v.file = attributes(m[3]);
    } else if (name == "Piece" && !closing) {
      v.piece = attributes(m[3]);
    } else if (!closing) {
      section = name;
    }
  }
  EXPECT_EQ(v.file["type"], "PolyData");
  // Every array has one tuple per point / cell of its section.
  const std::size_t points = v.count("NumberOfPoints");
  const std::size_t cells = v.count("NumberOfVerts") + v.count("NumberOfPolys") + v.count("NumberOfLines");
  EXPECT_EQ(v.count("NumberOfStrips"), 0u);
  for (const auto& [sec, arrays] : v.sections)
    for (const auto& [name, a] : arrays) {
      const std::size_t n = a.values.size() / static_cast<std::size_t>(a.components());
      EXPECT_EQ(a.values.size() % static_cast<std::size_t>(a.components()), 0u) << sec << '/' << name;
      if (sec == "PointData" || sec == "Points") {
        EXPECT_EQ(n, points) << sec << '/' << name;
      } else if (sec == "CellData") {
        EXPECT_EQ(n, cells) << sec << '/' << name;
      } else if (sec == "FieldData") {
        EXPECT_EQ(a.attr.at("NumberOfTuples"), std::to_string(n)) << name;
      }
    }
  // Cell blocks: one offset per cell, the last one the connectivity's length, every
  // index a point; an empty block is left out.
  for (const char* block : {"Verts", "Polys"}) {
    const std::size_t n = v.count(block == std::string("Verts") ? "NumberOfVerts" : "NumberOfPolys");
    if (n == 0) {
      EXPECT_EQ(v.sections.count(block), 0u) << block;
      continue;
    }
    const Array& off = v.at(block, "offsets");
    const Array& con = v.at(block, "connectivity");
    EXPECT_EQ(off.values.size(), n) << block;
    EXPECT_EQ(off.values.back(), static_cast<double>(con.values.size())) << block;
    for (double k : con.values) EXPECT_LT(k, static_cast<double>(points)) << block;
  }
  return v;
}

// The cell `c` of a block as point indices.
std::vector<int> cell(const Vtp& v, const char* block, std::size_t c) {
  const std::vector<double>& off = v.at(block, "offsets").values;
  const std::vector<double>& con = v.at(block, "connectivity").values;
  const auto from = static_cast<std::size_t>(c == 0 ? 0.0 : off[c - 1]), to = static_cast<std::size_t>(off[c]);
  return std::vector<int>(con.begin() + static_cast<long>(from), con.begin() + static_cast<long>(to));
}

VtkBody cube(int id, const Vec3& lo) {
  VtkBody b;
  b.id = id;
  b.velocity = Vec3(0.1 * id, 0.0, -1.0);
  b.angular_velocity = Vec3(0.0, 0.5 * id, 2.0);
  b.scale = 1.25;
  b.volume = 1.25 * 1.25 * 1.25;  // a unit cube at scale 1.25
  for (int i = 0; i < 8; ++i) b.vertices.push_back(lo + Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  b.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return b;
}

TEST(VtkWriter, ParticlesHaveConsistentCountsAndTheirBodiesData) {
  const fs::path d = temp_dir();
  const fs::path path = d / "particles.vtp";
  VtkBody sphere;
  sphere.id = 7;
  sphere.vertices = {Vec3(5, 5, 5)};
  sphere.sphere_radius = 0.75;
  sphere.volume = 4.0 / 3.0 * M_PI * 0.75 * 0.75 * 0.75;
  sphere.velocity = Vec3(1, 2, 3);
  sphere.angular_velocity = Vec3(-4, 0.5, 0);
  write_particles_vtp(path.string(), {cube(0, Vec3::Zero()), sphere, cube(1, Vec3(3, 0, 0))}, {2.0000000000000004, 500});
  EXPECT_FALSE(fs::exists(path.string() + ".partial"));
  const Vtp v = parse(read_text(path));
  EXPECT_EQ(v.count("NumberOfPoints"), 17u);
  EXPECT_EQ(v.count("NumberOfVerts"), 1u);
  EXPECT_EQ(v.count("NumberOfPolys"), 12u);
  // The time to the last bit, and the step.
  EXPECT_EQ(v.at("FieldData", "TimeValue").values, std::vector<double>{2.0000000000000004});
  EXPECT_EQ(v.at("FieldData", "step").values, std::vector<double>{500});
  // The sphere's centre is point 8; the second cube's faces index its own points after it.
  EXPECT_EQ(cell(v, "Verts", 0), std::vector<int>{8});
  EXPECT_EQ(cell(v, "Polys", 6), (std::vector<int>{9, 11, 12, 10}));
  // Cell data in cell order: the sphere's cell, then 6 faces of body 0, 6 of body 1.
  const std::vector<double>& cell_id = v.at("CellData", "body_id").values;
  ASSERT_EQ(cell_id.size(), 13u);
  EXPECT_EQ(cell_id[0], 7);
  EXPECT_EQ(cell_id[1], 0);
  EXPECT_EQ(cell_id[12], 1);
  const std::vector<double>& cell_w = v.at("CellData", "angular_velocity").values;
  EXPECT_EQ(std::vector<double>(cell_w.begin(), cell_w.begin() + 3), (std::vector<double>{-4, 0.5, 0}));
  EXPECT_EQ(cell_w[3 * 12 + 1], 0.5);
  // Point data in point order: cube 0, the sphere, cube 1.
  const std::vector<double>& radius = v.at("PointData", "radius").values;
  EXPECT_EQ(radius[0], 0.0);
  EXPECT_EQ(radius[8], 0.75);
  EXPECT_EQ(v.at("PointData", "body_id").values[8], 7);
  EXPECT_EQ(v.at("PointData", "body_id").values[9], 1);
  const std::vector<double>& vel = v.at("PointData", "velocity").values;
  EXPECT_EQ(std::vector<double>(vel.begin() + 24, vel.begin() + 27), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(v.at("PointData", "scale").values[0], 1.25);
  EXPECT_EQ(v.at("PointData", "scale").values[8], 1.0);
  // Every body has a size: the cube's equivalent radius is that of a sphere of volume
  // 1.25^3, the sphere's its radius (12 digits written).
  const std::vector<double>& req = v.at("PointData", "equivalent_radius").values;
  EXPECT_NEAR(req[0], 1.25 * std::cbrt(3.0 / (4.0 * M_PI)), 1e-11);
  EXPECT_NEAR(req[8], 0.75, 1e-11);
  EXPECT_NEAR(v.at("CellData", "volume").values[1], 1.953125, 1e-11);
  EXPECT_NEAR(v.at("CellData", "equivalent_radius").values[0], 0.75, 1e-11);
  const std::vector<double>& pts = v.at("Points", "Points").values;
  EXPECT_EQ(std::vector<double>(pts.begin() + 24, pts.begin() + 27), (std::vector<double>{5, 5, 5}));
  fs::remove_all(d);
}

TEST(VtkWriter, ContactsArePointsWithTheirForcesAndBodies) {
  const fs::path d = temp_dir();
  const fs::path path = d / "contacts.vtp";
  std::vector<VtkContact> c(3);
  c[0] = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 2.5), Vec3(0.5, 0, 0), -0.01, 0, 1};
  c[1] = {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.02, 1, 2};  // open: no force
  c[2] = {Vec3(1, 1, 0), Vec3(0, -1, 0), Vec3(0, -10, 0), Vec3(0, 0, 1), 0.0, 2, -3};  // wall 2
  write_contacts_vtp(path.string(), c, {0.5, 7});
  const Vtp v = parse(read_text(path));
  EXPECT_EQ(v.count("NumberOfPoints"), 3u);
  EXPECT_EQ(v.count("NumberOfVerts"), 3u);
  EXPECT_EQ(v.count("NumberOfPolys"), 0u);
  EXPECT_EQ(cell(v, "Verts", 2), std::vector<int>{2});
  EXPECT_EQ(v.at("PointData", "normal_force_magnitude").values, (std::vector<double>{2.5, 0, 10}));
  EXPECT_EQ(v.at("PointData", "gap").values, (std::vector<double>{-0.01, 0.02, 0}));
  EXPECT_EQ(v.at("PointData", "body_a").values, (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(v.at("PointData", "body_b").values, (std::vector<double>{1, 2, -3}));
  const std::vector<double>& ft = v.at("PointData", "tangential_force").values;
  EXPECT_EQ(std::vector<double>(ft.begin(), ft.begin() + 3), (std::vector<double>{0.5, 0, 0}));
  const std::vector<double>& fn = v.at("PointData", "normal_force").values;
  EXPECT_EQ(std::vector<double>(fn.begin() + 6, fn.end()), (std::vector<double>{0, -10, 0}));
  const std::vector<double>& pts = v.at("Points", "Points").values;
  EXPECT_EQ(std::vector<double>(pts.begin() + 6, pts.end()), (std::vector<double>{1, 1, 0}));
  EXPECT_EQ(v.at("PointData", "normal").values.size(), 9u);
  fs::remove_all(d);
}

TEST(VtkWriter, ForceChainsAreLinesBetweenTheCentresWithForcesAndStatus) {
  const fs::path d = temp_dir();
  std::vector<VtkContact> c(3);
  c[0] = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 2.5), Vec3(0.5, 0, 0), -0.01, 0, 1,
          Vec3(0, 0, 1.5), Vec3(0, 0, 0.5), kContactStick};
  c[1] = {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.02, 1, 2, Vec3(1.5, 0, 0), Vec3(0.5, 0, 0),
          kContactOpen};
  c[2] = {Vec3(1, 1, 0), Vec3(0, -1, 0), Vec3(0, -10, 0), Vec3(0, 0, 3), 0.0, 2, -3, Vec3(1, 1.5, 0), Vec3(1, 1, 0),
          kContactSlip};  // against wall 2: to the contact point
  write_force_chains_vtp((d / "f.vtp").string(), c, {0.5, 7});
  const Vtp v = parse(read_text(d / "f.vtp"));
  EXPECT_EQ(v.count("NumberOfPoints"), 6u);
  EXPECT_EQ(v.count("NumberOfLines"), 3u);
  EXPECT_EQ(v.count("NumberOfVerts"), 0u);
  EXPECT_EQ(cell(v, "Lines", 2), (std::vector<int>{4, 5}));
  const std::vector<double>& pts = v.at("Points", "Points").values;
  EXPECT_EQ(std::vector<double>(pts.begin() + 12, pts.end()), (std::vector<double>{1, 1.5, 0, 1, 1, 0}));
  EXPECT_EQ(v.at("CellData", "normal_force").values, (std::vector<double>{2.5, 0, 10}));
  EXPECT_EQ(v.at("CellData", "tangential_force").values, (std::vector<double>{0.5, 0, 3}));
  EXPECT_EQ(v.at("CellData", "status").values, (std::vector<double>{1, 0, 2}));
  EXPECT_EQ(v.at("CellData", "body_b").values, (std::vector<double>{1, 2, -3}));
  c[1].status = 7;
  EXPECT_THROW(write_force_chains_vtp((d / "g.vtp").string(), c, {0.5, 7}), std::invalid_argument);
  EXPECT_FALSE(fs::exists(d / "g.vtp"));
  fs::remove_all(d);
}

TEST(VtkWriter, ContainerPolygonsCarryTheirWalls) {
  const fs::path d = temp_dir();
  ContainerMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.polygons = {{0, 1, 2, 3}, {0, 1, 4}};
  m.wall = {0, 3};
  write_container_vtp((d / "c.vtp").string(), m, {Vec3::UnitZ(), Vec3::UnitY()}, {4.5, 0.0}, {1.0, 1});
  const Vtp v = parse(read_text(d / "c.vtp"));
  EXPECT_EQ(v.count("NumberOfPoints"), 5u);
  EXPECT_EQ(v.count("NumberOfPolys"), 2u);
  EXPECT_EQ(cell(v, "Polys", 1), (std::vector<int>{0, 1, 4}));
  EXPECT_EQ(v.at("CellData", "wall_index").values, (std::vector<double>{0, 3}));
  EXPECT_EQ(v.at("CellData", "side_id").values, (std::vector<double>{-1, -4}));  // as the contacts' body_b
  EXPECT_EQ(v.at("CellData", "normal_force").values, (std::vector<double>{4.5, 0}));
  EXPECT_EQ(v.at("CellData", "normal").values, (std::vector<double>{0, 0, 1, 0, 1, 0}));
  fs::remove_all(d);
}

TEST(VtkWriter, EmptyInputStillGivesAValidFile) {
  const fs::path d = temp_dir();
  write_contacts_vtp((d / "none.vtp").string(), {}, {});
  write_particles_vtp((d / "nobody.vtp").string(), {}, {});
  write_container_vtp((d / "nowall.vtp").string(), {}, {}, {}, {});
  for (const char* f : {"none.vtp", "nobody.vtp", "nowall.vtp"}) {
    const Vtp v = parse(read_text(d / f));
    EXPECT_EQ(v.count("NumberOfPoints"), 0u) << f;
    EXPECT_EQ(v.at("FieldData", "TimeValue").values, std::vector<double>{0.0}) << f;
  }
  fs::remove_all(d);
}

TEST(VtkWriter, InvalidInputLeavesNoFile) {
  const fs::path d = temp_dir();
  const std::string path = (d / "bad.vtp").string();
  VtkBody bad = cube(0, Vec3::Zero());
  bad.faces[2][1] = 8;  // out of range
  EXPECT_THROW(write_particles_vtp(path, {bad}, {}), std::invalid_argument);
  VtkBody flat = cube(0, Vec3::Zero());
  flat.faces[0] = {0, 1};
  EXPECT_THROW(write_particles_vtp(path, {flat}, {}), std::invalid_argument);
  VtkBody spinning = cube(0, Vec3::Zero());
  spinning.angular_velocity.x() = std::nan("");
  EXPECT_THROW(write_particles_vtp(path, {spinning}, {}), std::invalid_argument);
  EXPECT_THROW(write_particles_vtp(path, {}, {std::nan(""), 0}), std::invalid_argument);
  VtkContact c;
  c.tangential_force.y() = HUGE_VAL;
  EXPECT_THROW(write_contacts_vtp(path, {c}, {}), std::invalid_argument);
  ContainerMesh m;
  m.points = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()};
  m.polygons = {{0, 1, 2}};
  m.wall = {0};
  EXPECT_THROW(write_container_vtp(path, m, {Vec3::UnitZ()}, {}, {}), std::invalid_argument);  // no force
  m.polygons = {{0, 1, 3}};
  EXPECT_THROW(write_container_vtp(path, m, {Vec3::UnitZ()}, {0.0}, {}), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(write_contacts_vtp((d / "no-such-dir" / "x.vtp").string(), {}, {}), std::runtime_error);
  fs::remove_all(d);
}

}  // namespace
}  // namespace ratchet

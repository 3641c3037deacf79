// The VTK XML PolyData writers, in both encodings (zlib-compressed appended binary and
// ASCII): counts that agree with each other (points, cells, tuples of every array), cell
// order and offsets, the arrays' values, the time field, the same values bit for bit in
// both encodings, and no file at all for bad input. scripts/tests/test_vtk_output.py
// reads real runs' files back with VTK's own reader.
#include "ratchet/observe/vtk_writer.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include "support/test_files.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdint>
#include <cstring>
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

// Every test runs for both encodings (observe/vtk_xml.hpp).
class VtkWriter : public ::testing::TestWithParam<VtkEncoding> {};

// A minimal reader of the XML this writer produces: every element's attributes, and
// each DataArray's numbers under its section (FieldData, PointData, CellData, Points,
// Verts, Lines, Polys), inline text or zlib-compressed appended data.
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

std::uint64_t u64_at(const std::string& bytes, std::size_t at) {
  EXPECT_LE(at + 8, bytes.size());
  std::uint64_t x = 0;
  if (at + 8 <= bytes.size()) std::memcpy(&x, bytes.data() + at, 8);
  return x;
}

// The values of an appended array at `offset` of the raw data: the UInt64 header
// [blocks, block size, last block size, compressed sizes...], the zlib blocks, then
// the bytes as the array's type.
std::vector<double> appended_values(const std::string& raw, std::size_t offset, const std::string& type) {
  const std::uint64_t blocks = u64_at(raw, offset), block = u64_at(raw, offset + 8), last = u64_at(raw, offset + 16);
  std::string bytes;
  std::size_t at = offset + 24 + 8 * blocks;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t compressed = u64_at(raw, offset + 24 + 8 * b);
    uLongf size = static_cast<uLongf>(b + 1 == blocks && last != 0 ? last : block);
    std::string out(size, '\0');
    EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data() + at),
                         static_cast<uLong>(compressed)),
              Z_OK);
    bytes += out.substr(0, size);
    at += compressed;
  }
  std::vector<double> values;
  auto take = [&](auto zero) {
    using T = decltype(zero);
    EXPECT_EQ(bytes.size() % sizeof(T), 0u) << type;
    for (std::size_t i = 0; i + sizeof(T) <= bytes.size(); i += sizeof(T)) {
      T x;
      std::memcpy(&x, bytes.data() + i, sizeof(T));
      values.push_back(static_cast<double>(x));
    }
  };
  if (type == "Float64") take(0.0);
  else if (type == "Int32") take(std::int32_t{0});
  else if (type == "Int64") take(std::int64_t{0});
  else ADD_FAILURE() << "unexpected type " << type;
  return values;
}

Vtp parse(const std::string& file) {
  Vtp v;
  EXPECT_EQ(file.rfind("<?xml version=\"1.0\"?>\n", 0), 0u);
  // The raw bytes after "_" may hold anything: the XML is what comes before them.
  const std::string appended_tag = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t raw_at = file.find(appended_tag);
  const std::string xml = file.substr(0, raw_at);
  const std::string raw = raw_at == std::string::npos ? "" : file.substr(raw_at + appended_tag.size());
  if (raw_at != std::string::npos) EXPECT_EQ(raw.substr(raw.size() - 28), "\n</AppendedData>\n</VTKFile>\n");
  static const std::regex tag(R"re(<(/?)(\w+)([^>]*?)(/?)>)re");
  std::string section;
  Array* open = nullptr;
  std::size_t text_from = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    const bool closing = m[1] == "/";
    const std::string name = m[2];
    if (name == "DataArray" && m[4] == "/") {  // appended: no text, an offset into the raw data
      Array a;
      a.attr = attributes(m[3]);
      EXPECT_EQ(a.attr["format"], "appended");
      EXPECT_NE(raw_at, std::string::npos);
      a.values = appended_values(raw, std::stoul(a.attr.at("offset")), a.attr["type"]);
      Array& slot = v.sections[section][a.attr["Name"]];
      EXPECT_TRUE(slot.attr.empty()) << "two arrays " << a.attr["Name"] << " in " << section;
      slot = a;
    } else if (name == "DataArray" && closing) {
      std::istringstream in(xml.substr(text_from, static_cast<std::size_t>(m.position()) - text_from));
      for (std::string word; in >> word;) open->values.push_back(std::stod(word));
      open = nullptr;
    } else if (name == "DataArray") {
      Array a;
      a.attr = attributes(m[3]);
      EXPECT_EQ(a.attr["format"], "ascii");  // inline text: always in FieldData, everywhere in ASCII files
      if (section != "FieldData") EXPECT_EQ(raw_at, std::string::npos) << a.attr["Name"];
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
  EXPECT_EQ(v.file["header_type"], "UInt64");
  EXPECT_EQ(v.file.count("compressor") == 1, raw_at != std::string::npos);
  if (raw_at != std::string::npos) EXPECT_EQ(v.file["compressor"], "vtkZLibDataCompressor");
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
  for (const std::string block : {"Verts", "Lines", "Polys"}) {
    const std::size_t n = v.count(("NumberOf" + block).c_str());
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

TEST_P(VtkWriter, ParticlesHaveConsistentCountsAndTheirBodiesData) {
  const fs::path d = temp_dir();
  const fs::path path = d / "particles.vtp";
  VtkBody sphere;
  sphere.id = 7;
  sphere.vertices = {Vec3(5, 5, 5)};
  sphere.sphere_radius = 0.75;
  sphere.volume = 4.0 / 3.0 * M_PI * 0.75 * 0.75 * 0.75;
  sphere.velocity = Vec3(1, 2, 3);
  sphere.angular_velocity = Vec3(-4, 0.5, 0);
  write_particles_vtp(path.string(), {cube(0, Vec3::Zero()), sphere, cube(1, Vec3(3, 0, 0))}, {2.0000000000000004, 500},
                      GetParam());
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
  // 1.25^3, the sphere's its radius (to round-off of the cube root).
  const std::vector<double>& req = v.at("PointData", "equivalent_radius").values;
  EXPECT_NEAR(req[0], 1.25 * std::cbrt(3.0 / (4.0 * M_PI)), 1e-11);
  EXPECT_NEAR(req[8], 0.75, 1e-11);
  EXPECT_NEAR(v.at("CellData", "volume").values[1], 1.953125, 1e-11);
  EXPECT_NEAR(v.at("CellData", "equivalent_radius").values[0], 0.75, 1e-11);
  const std::vector<double>& pts = v.at("Points", "Points").values;
  EXPECT_EQ(std::vector<double>(pts.begin() + 24, pts.begin() + 27), (std::vector<double>{5, 5, 5}));
  fs::remove_all(d);
}

TEST_P(VtkWriter, ContactsArePointsWithTheirForcesAndBodies) {
  const fs::path d = temp_dir();
  const fs::path path = d / "contacts.vtp";
  std::vector<VtkContact> c(3);
  c[0] = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 2.5), Vec3(0.5, 0, 0), -0.01, 0, 1};
  c[1] = {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.02, 1, 2};  // open: no force
  c[2] = {Vec3(1, 1, 0), Vec3(0, -1, 0), Vec3(0, -10, 0), Vec3(0, 0, 1), 0.0, 2, -3};  // wall 2
  write_contacts_vtp(path.string(), c, {0.5, 7}, GetParam());
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

TEST_P(VtkWriter, ForceChainsAreLinesBetweenTheCentresWithForcesAndStatus) {
  const fs::path d = temp_dir();
  std::vector<VtkContact> c(3);
  c[0] = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 2.5), Vec3(0.5, 0, 0), -0.01, 0, 1,
          Vec3(0, 0, 1.5), Vec3(0, 0, 0.5), kContactStick};
  c[1] = {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.02, 1, 2, Vec3(1.5, 0, 0), Vec3(0.5, 0, 0),
          kContactOpen};
  c[2] = {Vec3(1, 1, 0), Vec3(0, -1, 0), Vec3(0, -10, 0), Vec3(0, 0, 3), 0.0, 2, -3, Vec3(1, 1.5, 0), Vec3(1, 1, 0),
          kContactSlip};  // against wall 2: to the contact point
  write_force_chains_vtp((d / "f.vtp").string(), c, {0.5, 7}, GetParam());
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
  EXPECT_THROW(write_force_chains_vtp((d / "g.vtp").string(), c, {0.5, 7}, GetParam()), std::invalid_argument);
  EXPECT_FALSE(fs::exists(d / "g.vtp"));
  fs::remove_all(d);
}

TEST_P(VtkWriter, ContainerPolygonsCarryTheirWalls) {
  const fs::path d = temp_dir();
  ContainerMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.polygons = {{0, 1, 2, 3}, {0, 1, 4}};
  m.wall = {0, 3};
  write_container_vtp((d / "c.vtp").string(), m, {Vec3::UnitZ(), Vec3::UnitY()}, {4.5, 0.0}, {1.0, 1}, GetParam());
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

TEST_P(VtkWriter, EmptyInputStillGivesAValidFile) {
  const fs::path d = temp_dir();
  write_contacts_vtp((d / "none.vtp").string(), {}, {}, GetParam());
  write_particles_vtp((d / "nobody.vtp").string(), {}, {}, GetParam());
  write_container_vtp((d / "nowall.vtp").string(), {}, {}, {}, {}, GetParam());
  for (const char* f : {"none.vtp", "nobody.vtp", "nowall.vtp"}) {
    const Vtp v = parse(read_text(d / f));
    EXPECT_EQ(v.count("NumberOfPoints"), 0u) << f;
    EXPECT_EQ(v.at("FieldData", "TimeValue").values, std::vector<double>{0.0}) << f;
  }
  fs::remove_all(d);
}

TEST_P(VtkWriter, InvalidInputLeavesNoFile) {
  const fs::path d = temp_dir();
  const std::string path = (d / "bad.vtp").string();
  VtkBody bad = cube(0, Vec3::Zero());
  bad.faces[2][1] = 8;  // out of range
  EXPECT_THROW(write_particles_vtp(path, {bad}, {}, GetParam()), std::invalid_argument);
  VtkBody flat = cube(0, Vec3::Zero());
  flat.faces[0] = {0, 1};
  EXPECT_THROW(write_particles_vtp(path, {flat}, {}, GetParam()), std::invalid_argument);
  VtkBody spinning = cube(0, Vec3::Zero());
  spinning.angular_velocity.x() = std::nan("");
  EXPECT_THROW(write_particles_vtp(path, {spinning}, {}, GetParam()), std::invalid_argument);
  EXPECT_THROW(write_particles_vtp(path, {}, {std::nan(""), 0}, GetParam()), std::invalid_argument);
  VtkContact c;
  c.tangential_force.y() = HUGE_VAL;
  EXPECT_THROW(write_contacts_vtp(path, {c}, {}, GetParam()), std::invalid_argument);
  ContainerMesh m;
  m.points = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()};
  m.polygons = {{0, 1, 2}};
  m.wall = {0};
  EXPECT_THROW(write_container_vtp(path, m, {Vec3::UnitZ()}, {}, {}, GetParam()), std::invalid_argument);  // no force
  m.polygons = {{0, 1, 3}};
  EXPECT_THROW(write_container_vtp(path, m, {Vec3::UnitZ()}, {0.0}, {}, GetParam()), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
  EXPECT_THROW(write_contacts_vtp((d / "no-such-dir" / "x.vtp").string(), {}, {}, GetParam()), std::runtime_error);
  fs::remove_all(d);
}

// The two encodings hold the same arrays to the last bit (ASCII writes the shortest text
// that reads back to the same double), with values that no short decimal holds.
TEST(VtkEncodings, BinaryAndAsciiHoldTheSameArrays) {
  const fs::path d = temp_dir();
  std::vector<VtkBody> bodies;
  std::vector<VtkContact> contacts;
  for (int i = 0; i < 40; ++i) {
    VtkBody b = cube(i, Vec3(i / 3.0, std::sqrt(2.0) * i, 1e-300 * i));
    b.velocity = Vec3(0.1 + 0.2 * i, -1.0 / (i + 7.0), std::exp(-i));
    b.scale = 1.0 + 1e-16 * i;
    bodies.push_back(b);
    VtkContact c;
    c.point = b.vertices[3];
    c.normal = Vec3(0.6, 0.8, 0.0);
    c.normal_force = Vec3(1.0 / 3.0, 2.0 / 3.0, i * M_PI);
    c.tangential_force = Vec3(0.0, 1e-17 * i, -0.1 * i);
    c.gap = -1e-5 / (i + 1.0);
    c.body_a = i;
    c.body_b = i % 3 == 0 ? -1 - i % 5 : i + 1;
    c.from = b.vertices[0];
    c.to = b.vertices[7];
    c.status = i % 3;
    contacts.push_back(c);
  }
  const VtkTime time{1.0 / 3.0, 123456789012};
  for (const std::string kind : {"particles", "contacts", "force_chains"}) {
    SCOPED_TRACE(kind);
    std::map<VtkEncoding, Vtp> read;
    for (VtkEncoding e : {VtkEncoding::Binary, VtkEncoding::Ascii}) {
      const std::string path = (d / (kind + "_" + vtk_encoding_name(e) + ".vtp")).string();
      if (kind == "particles") write_particles_vtp(path, bodies, time, e);
      else if (kind == "contacts") write_contacts_vtp(path, contacts, time, e);
      else write_force_chains_vtp(path, contacts, time, e);
      read[e] = parse(read_text(path));
    }
    const Vtp& bin = read.at(VtkEncoding::Binary);
    const Vtp& txt = read.at(VtkEncoding::Ascii);
    EXPECT_EQ(bin.piece, txt.piece);
    ASSERT_EQ(bin.sections.size(), txt.sections.size());
    for (const auto& [section, arrays] : bin.sections) {
      ASSERT_EQ(txt.sections.count(section), 1u) << section;
      ASSERT_EQ(arrays.size(), txt.sections.at(section).size()) << section;
      for (const auto& [name, a] : arrays) {
        const Array& t = txt.at(section, name);
        EXPECT_EQ(a.attr.at("type"), t.attr.at("type")) << section << '/' << name;
        EXPECT_EQ(a.components(), t.components()) << section << '/' << name;
        ASSERT_EQ(a.values.size(), t.values.size()) << section << '/' << name;
        EXPECT_FALSE(a.values.empty()) << section << '/' << name;
        // Bit for bit: memcmp also tells -0 from 0.
        EXPECT_EQ(std::memcmp(a.values.data(), t.values.data(), a.values.size() * sizeof(double)), 0)
            << section << '/' << name;
      }
    }
    EXPECT_EQ(bin.at("FieldData", "TimeValue").values, std::vector<double>{1.0 / 3.0});
  }
  // What compression is for: the binary particles file is the smaller one.
  EXPECT_LT(fs::file_size(d / "particles_binary.vtp"), fs::file_size(d / "particles_ascii.vtp") / 2);
  fs::remove_all(d);
}

INSTANTIATE_TEST_SUITE_P(Encodings, VtkWriter, ::testing::Values(VtkEncoding::Binary, VtkEncoding::Ascii),
                         [](const auto& info) { return std::string(vtk_encoding_name(info.param)); });

}  // namespace
}  // namespace ratchet

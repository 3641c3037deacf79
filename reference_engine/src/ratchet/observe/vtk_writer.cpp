#include "ratchet/observe/vtk_writer.hpp"

#include <cmath>
#include <locale>
#include <ostream>
#include <stdexcept>

#include "ratchet/core/contact_side.hpp"
#include "ratchet/io/atomic_file.hpp"

namespace ratchet {
namespace {

// 12 significant digits: far below what a picture resolves, and a third smaller than
// round-trip precision (17); the output is still deterministic. The time is written
// to round trip, as in the CSVs, so that it matches their t column exactly.
constexpr int kDigits = 12;
constexpr int kTimeDigits = 17;

void check_finite(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what + " is not finite");
}

void put(std::ostream& out, const Vec3& p) { out << p.x() << ' ' << p.y() << ' ' << p.z(); }

// Connectivity and offsets of one cell block (Verts or Polys), as VTK stores them.
struct CellBlock {
  std::vector<std::int64_t> connectivity, offsets;
  template <class Indices>
  void add(const Indices& indices, std::int64_t first) {
    for (const auto k : indices) connectivity.push_back(first + static_cast<std::int64_t>(k));
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  std::size_t size() const { return offsets.size(); }
};

// One <DataArray> with `count` tuples; each(i) writes tuple i (components separated by
// spaces), one tuple per line. Field data (not tied to points or cells) must state its
// tuple count.
template <class Each>
void data_array(std::ostream& out, const char* type, const char* name, int components, std::size_t count,
                Each&& each, bool field_data = false) {
  out << "<DataArray type=\"" << type << "\" Name=\"" << name << '"';
  if (components > 1) out << " NumberOfComponents=\"" << components << '"';
  if (field_data) out << " NumberOfTuples=\"" << count << '"';
  out << " format=\"ascii\">\n";
  for (std::size_t i = 0; i < count; ++i) {
    each(i);
    out << '\n';
  }
  out << "</DataArray>\n";
}

// The file's head up to the opening <Piece>: field data TimeValue and step.
void begin(std::ostream& out, const VtkTime& time, std::size_t points, std::size_t verts, std::size_t polys,
           std::size_t lines = 0) {
  out.imbue(std::locale::classic());  // '.' decimal point whatever the global locale
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
         "<PolyData>\n<FieldData>\n";
  out.precision(kTimeDigits);
  data_array(out, "Float64", "TimeValue", 1, 1, [&](std::size_t) { out << time.t; }, true);
  data_array(out, "Int64", "step", 1, 1, [&](std::size_t) { out << time.step; }, true);
  out.precision(kDigits);
  out << "</FieldData>\n<Piece NumberOfPoints=\"" << points << "\" NumberOfVerts=\"" << verts
      << "\" NumberOfLines=\"" << lines << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << polys << "\">\n";
}

void points(std::ostream& out, const std::vector<Vec3>& p) {
  out << "<Points>\n";
  data_array(out, "Float64", "Points", 3, p.size(), [&](std::size_t i) { put(out, p[i]); });
  out << "</Points>\n";
}

// A cell block; left out when empty (the reader takes a missing block as no cells).
void cells(std::ostream& out, const char* tag, const CellBlock& c) {
  if (c.size() == 0) return;
  out << '<' << tag << ">\n";
  out << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < c.connectivity.size(); ++i) out << c.connectivity[i] << (i % 16 == 15 ? '\n' : ' ');
  out << "\n</DataArray>\n";
  data_array(out, "Int64", "offsets", 1, c.offsets.size(), [&](std::size_t i) { out << c.offsets[i]; });
  out << "</" << tag << ">\n";
}

void end(std::ostream& out) { out << "</Piece>\n</PolyData>\n</VTKFile>\n"; }

}  // namespace

void write_particles_vtp(const std::string& path, const std::vector<VtkBody>& bodies, const VtkTime& time) {
  check_finite(std::isfinite(time.t), "write_particles_vtp: time");
  // Validate everything first so that a bad body leaves no file behind.
  std::vector<Vec3> pts;
  std::vector<const VtkBody*> point_body;      // the body of each point
  std::vector<const VtkBody*> cell_body;       // the body of each cell: Verts first, then Polys
  CellBlock verts, polys;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const VtkBody& b = bodies[i];
    const std::string what = "write_particles_vtp: body " + std::to_string(i) + " (id " + std::to_string(b.id) + ")";
    check_finite(b.velocity.allFinite(), what + " velocity");
    check_finite(b.angular_velocity.allFinite(), what + " angular velocity");
    check_finite(std::isfinite(b.scale), what + " scale");
    check_finite(std::isfinite(b.volume), what + " volume");
    if (b.volume < 0.0) throw std::invalid_argument(what + ": negative volume");
    for (const Vec3& v : b.vertices) check_finite(v.allFinite(), what + " vertex");
    const auto first = static_cast<std::int64_t>(pts.size());
    if (b.sphere_radius > 0.0) {
      if (b.vertices.size() != 1 || !b.faces.empty())
        throw std::invalid_argument(what + ": a sphere needs exactly one vertex (its centre) and no faces");
      check_finite(std::isfinite(b.sphere_radius), what + " radius");
      verts.add(std::vector<int>{0}, first);
    } else {
      if (b.faces.empty()) throw std::invalid_argument(what + ": a polyhedron needs faces");
      for (const auto& f : b.faces) {
        if (f.size() < 3) throw std::invalid_argument(what + ": a face has fewer than 3 vertices");
        for (int k : f)
          if (k < 0 || static_cast<std::size_t>(k) >= b.vertices.size())
            throw std::invalid_argument(what + ": face index " + std::to_string(k) + " out of range");
        polys.add(f, first);
      }
    }
    pts.insert(pts.end(), b.vertices.begin(), b.vertices.end());
    point_body.insert(point_body.end(), b.vertices.size(), &b);
  }
  for (const VtkBody& b : bodies)
    if (b.sphere_radius > 0.0) cell_body.push_back(&b);
  for (const VtkBody& b : bodies)
    if (!(b.sphere_radius > 0.0)) cell_body.insert(cell_body.end(), b.faces.size(), &b);

  AtomicFile file(path);
  std::ostream& out = file.stream();
  begin(out, time, pts.size(), verts.size(), polys.size());
  auto body_arrays = [&](const std::vector<const VtkBody*>& of) {
    const std::size_t n = of.size();
    data_array(out, "Int32", "body_id", 1, n, [&](std::size_t i) { out << of[i]->id; });
    data_array(out, "Float64", "velocity", 3, n, [&](std::size_t i) { put(out, of[i]->velocity); });
    data_array(out, "Float64", "angular_velocity", 3, n, [&](std::size_t i) { put(out, of[i]->angular_velocity); });
    data_array(out, "Float64", "scale", 1, n, [&](std::size_t i) { out << of[i]->scale; });
    // The size of every body, spheres and polyhedra alike, to colour or filter by.
    data_array(out, "Float64", "volume", 1, n, [&](std::size_t i) { out << of[i]->volume; });
    data_array(out, "Float64", "equivalent_radius", 1, n,
               [&](std::size_t i) { out << std::cbrt(3.0 * of[i]->volume / (4.0 * M_PI)); });
  };
  out << "<PointData>\n";
  body_arrays(point_body);
  data_array(out, "Float64", "radius", 1, pts.size(), [&](std::size_t i) {
    out << (point_body[i]->sphere_radius > 0.0 ? point_body[i]->sphere_radius : 0.0);
  });
  out << "</PointData>\n<CellData>\n";
  body_arrays(cell_body);
  out << "</CellData>\n";
  points(out, pts);
  cells(out, "Verts", verts);
  cells(out, "Polys", polys);
  end(out);
  file.commit();
}

void write_contacts_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time) {
  check_finite(std::isfinite(time.t), "write_contacts_vtp: time");
  std::vector<Vec3> pts;
  CellBlock verts;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const VtkContact& c = contacts[i];
    const std::string what = "write_contacts_vtp: contact " + std::to_string(i);
    check_finite(c.point.allFinite(), what + " point");
    check_finite(c.normal.allFinite(), what + " normal");
    check_finite(c.normal_force.allFinite() && c.tangential_force.allFinite(), what + " force");
    check_finite(std::isfinite(c.gap), what + " gap");
    pts.push_back(c.point);
    verts.add(std::vector<std::size_t>{i}, 0);
  }
  AtomicFile file(path);
  std::ostream& out = file.stream();
  begin(out, time, pts.size(), verts.size(), 0);
  const std::size_t n = contacts.size();
  out << "<PointData>\n";
  data_array(out, "Float64", "normal", 3, n, [&](std::size_t i) { put(out, contacts[i].normal); });
  data_array(out, "Float64", "normal_force", 3, n, [&](std::size_t i) { put(out, contacts[i].normal_force); });
  data_array(out, "Float64", "tangential_force", 3, n, [&](std::size_t i) { put(out, contacts[i].tangential_force); });
  data_array(out, "Float64", "normal_force_magnitude", 1, n,
             [&](std::size_t i) { out << contacts[i].normal.dot(contacts[i].normal_force); });
  data_array(out, "Float64", "gap", 1, n, [&](std::size_t i) { out << contacts[i].gap; });
  data_array(out, "Int32", "body_a", 1, n, [&](std::size_t i) { out << contacts[i].body_a; });
  data_array(out, "Int32", "body_b", 1, n, [&](std::size_t i) { out << contacts[i].body_b; });
  out << "</PointData>\n";
  points(out, pts);
  cells(out, "Verts", verts);
  end(out);
  file.commit();
}

void write_force_chains_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time) {
  check_finite(std::isfinite(time.t), "write_force_chains_vtp: time");
  std::vector<Vec3> pts;
  CellBlock lines;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const VtkContact& c = contacts[i];
    const std::string what = "write_force_chains_vtp: contact " + std::to_string(i);
    check_finite(c.from.allFinite() && c.to.allFinite(), what + " end");
    check_finite(c.normal_force.allFinite() && c.tangential_force.allFinite(), what + " force");
    if (c.status != kContactOpen && c.status != kContactStick && c.status != kContactSlip)
      throw std::invalid_argument(what + ": status " + std::to_string(c.status) + " is not 0, 1 or 2");
    pts.push_back(c.from);
    pts.push_back(c.to);
    lines.add(std::vector<std::size_t>{0, 1}, static_cast<std::int64_t>(2 * i));
  }
  AtomicFile file(path);
  std::ostream& out = file.stream();
  begin(out, time, pts.size(), 0, 0, lines.size());
  const std::size_t n = contacts.size();
  out << "<CellData>\n";
  data_array(out, "Float64", "normal_force", 1, n, [&](std::size_t i) { out << contacts[i].normal.dot(contacts[i].normal_force); });
  data_array(out, "Float64", "tangential_force", 1, n, [&](std::size_t i) { out << contacts[i].tangential_force.norm(); });
  data_array(out, "Int32", "status", 1, n, [&](std::size_t i) { out << contacts[i].status; });
  data_array(out, "Int32", "body_a", 1, n, [&](std::size_t i) { out << contacts[i].body_a; });
  data_array(out, "Int32", "body_b", 1, n, [&](std::size_t i) { out << contacts[i].body_b; });
  out << "</CellData>\n";
  points(out, pts);
  cells(out, "Lines", lines);
  end(out);
  file.commit();
}

void write_container_vtp(const std::string& path, const ContainerMesh& mesh, const std::vector<Vec3>& normal,
                         const std::vector<double>& normal_force, const VtkTime& time) {
  const std::string what = "write_container_vtp: ";
  check_finite(std::isfinite(time.t), what + "time");
  const std::size_t n = mesh.polygons.size();
  if (mesh.wall.size() != n || normal.size() != n || normal_force.size() != n)
    throw std::invalid_argument(what + "wall, normal and normal_force need one entry per polygon (" +
                                std::to_string(n) + ")");
  for (const Vec3& p : mesh.points) check_finite(p.allFinite(), what + "point");
  CellBlock polys;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& f = mesh.polygons[i];
    if (f.size() < 3) throw std::invalid_argument(what + "polygon " + std::to_string(i) + " has fewer than 3 points");
    for (int k : f)
      if (k < 0 || static_cast<std::size_t>(k) >= mesh.points.size())
        throw std::invalid_argument(what + "polygon " + std::to_string(i) + ": index " + std::to_string(k) +
                                    " out of range");
    if (mesh.wall[i] < 0) throw std::invalid_argument(what + "polygon " + std::to_string(i) + ": negative wall index");
    check_finite(normal[i].allFinite() && std::isfinite(normal_force[i]), what + "polygon " + std::to_string(i) + " data");
    polys.add(f, 0);
  }
  AtomicFile file(path);
  std::ostream& out = file.stream();
  begin(out, time, mesh.points.size(), 0, polys.size());
  out << "<CellData>\n";
  data_array(out, "Int32", "wall_index", 1, n, [&](std::size_t i) { out << mesh.wall[i]; });
  data_array(out, "Int32", "side_id", 1, n, [&](std::size_t i) { out << wall_side(mesh.wall[i]); });
  data_array(out, "Float64", "normal", 3, n, [&](std::size_t i) { put(out, normal[i]); });
  data_array(out, "Float64", "normal_force", 1, n, [&](std::size_t i) { out << normal_force[i]; });
  out << "</CellData>\n";
  points(out, mesh.points);
  cells(out, "Polys", polys);
  end(out);
  file.commit();
}

}  // namespace ratchet

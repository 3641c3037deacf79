#include "ratchet/observe/vtk_writer.hpp"

#include <cmath>
#include <locale>
#include <ostream>
#include <stdexcept>

#include "ratchet/io/atomic_file.hpp"

namespace ratchet {
namespace {

// 12 significant digits: far below what a picture resolves, and a third smaller than
// round-trip precision (17); the output is still deterministic.
constexpr int kDigits = 12;

// Legacy header: version line, one-line title (at most 255 characters), ASCII, dataset.
void header(std::ostream& out, const std::string& title) {
  std::string t = title.substr(0, 255);
  for (char& c : t)
    if (c == '\n' || c == '\r') c = ' ';
  out << "# vtk DataFile Version 3.0\n" << (t.empty() ? "ratchet" : t) << "\nASCII\nDATASET POLYDATA\n";
}

void prepare(std::ostream& out) {
  out.imbue(std::locale::classic());  // '.' decimal point whatever the global locale
  out.precision(kDigits);
}

void put(std::ostream& out, const Vec3& p) { out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n'; }

void check_finite(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what + " is not finite");
}

}  // namespace

void write_particles_vtk(const std::string& path, const std::vector<VtkBody>& bodies, const std::string& title) {
  // Validate everything first so that a bad body leaves no file behind.
  std::size_t points = 0, spheres = 0, polygons = 0, polygon_size = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const VtkBody& b = bodies[i];
    const std::string what = "write_particles_vtk: body " + std::to_string(i) + " (id " + std::to_string(b.id) + ")";
    check_finite(b.velocity.allFinite(), what + " velocity");
    for (const Vec3& v : b.vertices) check_finite(v.allFinite(), what + " vertex");
    if (b.sphere_radius > 0.0) {
      if (b.vertices.size() != 1 || !b.faces.empty())
        throw std::invalid_argument(what + ": a sphere needs exactly one vertex (its centre) and no faces");
      check_finite(std::isfinite(b.sphere_radius), what + " radius");
      ++spheres;
    } else {
      if (b.faces.empty()) throw std::invalid_argument(what + ": a polyhedron needs faces");
      for (const auto& f : b.faces) {
        if (f.size() < 3) throw std::invalid_argument(what + ": a face has fewer than 3 vertices");
        for (int k : f)
          if (k < 0 || static_cast<std::size_t>(k) >= b.vertices.size())
            throw std::invalid_argument(what + ": face index " + std::to_string(k) + " out of range");
        ++polygons;
        polygon_size += 1 + f.size();
      }
    }
    points += b.vertices.size();
  }

  AtomicFile file(path);
  std::ostream& out = file.stream();
  prepare(out);
  header(out, title);
  out << "POINTS " << points << " double\n";
  for (const VtkBody& b : bodies)
    for (const Vec3& v : b.vertices) put(out, v);

  // Each body's points start at its offset in the POINTS list.
  std::vector<std::size_t> offset(bodies.size());
  for (std::size_t i = 0, o = 0; i < bodies.size(); o += bodies[i].vertices.size(), ++i) offset[i] = o;
  if (spheres > 0) {
    out << "VERTICES " << spheres << ' ' << 2 * spheres << '\n';
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].sphere_radius > 0.0) out << "1 " << offset[i] << '\n';
  }
  if (polygons > 0) {
    out << "POLYGONS " << polygons << ' ' << polygon_size << '\n';
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (bodies[i].sphere_radius > 0.0) continue;
      for (const auto& f : bodies[i].faces) {
        out << f.size();
        for (int k : f) out << ' ' << offset[i] + static_cast<std::size_t>(k);
        out << '\n';
      }
    }
  }

  // Cell data in cell order: all VERTICES cells, then all POLYGONS cells.
  const std::size_t cells = spheres + polygons;
  if (cells > 0) {
    auto for_each_cell_body = [&](auto&& emit) {
      for (const VtkBody& b : bodies)
        if (b.sphere_radius > 0.0) emit(b);
      for (const VtkBody& b : bodies)
        if (!(b.sphere_radius > 0.0))
          for (std::size_t k = 0; k < b.faces.size(); ++k) emit(b);
    };
    out << "CELL_DATA " << cells << "\nSCALARS body_id int 1\nLOOKUP_TABLE default\n";
    for_each_cell_body([&](const VtkBody& b) { out << b.id << '\n'; });
    out << "VECTORS velocity double\n";
    for_each_cell_body([&](const VtkBody& b) { put(out, b.velocity); });
  }
  if (points > 0) {
    out << "POINT_DATA " << points << "\nSCALARS radius double 1\nLOOKUP_TABLE default\n";
    for (const VtkBody& b : bodies)
      for (std::size_t k = 0; k < b.vertices.size(); ++k) out << (b.sphere_radius > 0.0 ? b.sphere_radius : 0.0) << '\n';
  }
  file.commit();
}

void write_contact_network_vtk(const std::string& path, const std::vector<VtkContact>& contacts,
                               const std::string& title) {
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const VtkContact& c = contacts[i];
    const std::string what = "write_contact_network_vtk: contact " + std::to_string(i);
    check_finite(c.a.allFinite() && c.b.allFinite(), what + " end point");
    check_finite(std::isfinite(c.normal_force), what + " normal force");
  }
  AtomicFile file(path);
  std::ostream& out = file.stream();
  prepare(out);
  header(out, title);
  const std::size_t n = contacts.size();
  out << "POINTS " << 2 * n << " double\n";
  for (const VtkContact& c : contacts) {
    put(out, c.a);
    put(out, c.b);
  }
  if (n > 0) {
    out << "LINES " << n << ' ' << 3 * n << '\n';
    for (std::size_t i = 0; i < n; ++i) out << "2 " << 2 * i << ' ' << 2 * i + 1 << '\n';
    out << "CELL_DATA " << n << "\nSCALARS normal_force double 1\nLOOKUP_TABLE default\n";
    for (const VtkContact& c : contacts) out << c.normal_force << '\n';
    // The body ids as FIELD arrays: a legacy reader takes only the first SCALARS block
    // unless told to read all (vtkDataReader::ReadAllScalars), but always every FIELD array.
    out << "FIELD FieldData 2\nbody_a 1 " << n << " int\n";
    for (const VtkContact& c : contacts) out << c.body_a << '\n';
    out << "body_b 1 " << n << " int\n";
    for (const VtkContact& c : contacts) out << c.body_b << '\n';
  }
  file.commit();
}

}  // namespace ratchet

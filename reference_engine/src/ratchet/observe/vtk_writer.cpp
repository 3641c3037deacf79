#include "ratchet/observe/vtk_writer.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

#include "ratchet/core/contact_side.hpp"
#include "ratchet/io/atomic_file.hpp"

namespace ratchet {
namespace {

void check_finite(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what + " is not finite");
}

// Connectivity and offsets of one cell block (Verts, Lines or Polys), as VTK stores them.
struct CellBlock {
  std::vector<std::int64_t> connectivity, offsets;
  template <class Indices>
  void add(const Indices& indices, std::int64_t first) {
    for (const auto k : indices) connectivity.push_back(first + static_cast<std::int64_t>(k));
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  std::size_t size() const { return offsets.size(); }
};

// f(item) for every item, as one array (3 components for a Vec3).
template <class Item, class F>
auto gather(const std::vector<Item>& items, F&& f) {
  using T = std::decay_t<decltype(f(items.front()))>;
  if constexpr (std::is_same_v<T, Vec3>) {
    std::vector<double> out;
    out.reserve(3 * items.size());
    for (const Item& i : items) {
      const Vec3 v = f(i);
      out.insert(out.end(), {v.x(), v.y(), v.z()});
    }
    return out;
  } else {
    std::vector<T> out;
    out.reserve(items.size());
    for (const Item& i : items) out.push_back(f(i));
    return out;
  }
}

void points(VtkXml& xml, const std::vector<Vec3>& p) {
  xml.open("Points");
  xml.array("Points", 3, gather(p, [](const Vec3& v) { return v; }));
  xml.close("Points");
}

// A cell block; left out when empty (the reader takes a missing block as no cells).
void cells(VtkXml& xml, const char* tag, const CellBlock& c) {
  if (c.size() == 0) return;
  xml.open(tag);
  xml.array("connectivity", 1, c.connectivity);
  xml.array("offsets", 1, c.offsets);
  xml.close(tag);
}

}  // namespace

void write_particles_vtp(const std::string& path, const std::vector<VtkBody>& bodies, const VtkTime& time,
                         VtkEncoding encoding) {
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

  VtkXml xml(encoding, time, pts.size(), verts.size(), 0, polys.size());
  auto body_arrays = [&](const std::vector<const VtkBody*>& of) {
    xml.array("body_id", 1, gather(of, [](const VtkBody* b) { return static_cast<std::int32_t>(b->id); }));
    xml.array("velocity", 3, gather(of, [](const VtkBody* b) { return b->velocity; }));
    xml.array("angular_velocity", 3, gather(of, [](const VtkBody* b) { return b->angular_velocity; }));
    xml.array("scale", 1, gather(of, [](const VtkBody* b) { return b->scale; }));
    // The size of every body, spheres and polyhedra alike, to colour or filter by.
    xml.array("volume", 1, gather(of, [](const VtkBody* b) { return b->volume; }));
    xml.array("equivalent_radius", 1,
              gather(of, [](const VtkBody* b) { return std::cbrt(3.0 * b->volume / (4.0 * M_PI)); }));
  };
  xml.open("PointData");
  body_arrays(point_body);
  xml.array("radius", 1,
            gather(point_body, [](const VtkBody* b) { return b->sphere_radius > 0.0 ? b->sphere_radius : 0.0; }));
  xml.close("PointData");
  xml.open("CellData");
  body_arrays(cell_body);
  xml.close("CellData");
  points(xml, pts);
  cells(xml, "Verts", verts);
  cells(xml, "Polys", polys);
  write_file_atomic(path, xml.finish());
}

void write_contacts_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time,
                        VtkEncoding encoding) {
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
  VtkXml xml(encoding, time, pts.size(), verts.size(), 0, 0);
  using C = const VtkContact&;
  xml.open("PointData");
  xml.array("normal", 3, gather(contacts, [](C c) { return c.normal; }));
  xml.array("normal_force", 3, gather(contacts, [](C c) { return c.normal_force; }));
  xml.array("tangential_force", 3, gather(contacts, [](C c) { return c.tangential_force; }));
  xml.array("normal_force_magnitude", 1, gather(contacts, [](C c) { return c.normal.dot(c.normal_force); }));
  xml.array("gap", 1, gather(contacts, [](C c) { return c.gap; }));
  xml.array("body_a", 1, gather(contacts, [](C c) { return static_cast<std::int32_t>(c.body_a); }));
  xml.array("body_b", 1, gather(contacts, [](C c) { return static_cast<std::int32_t>(c.body_b); }));
  xml.close("PointData");
  points(xml, pts);
  cells(xml, "Verts", verts);
  write_file_atomic(path, xml.finish());
}

void write_force_chains_vtp(const std::string& path, const std::vector<VtkContact>& contacts, const VtkTime& time,
                            VtkEncoding encoding) {
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
  VtkXml xml(encoding, time, pts.size(), 0, lines.size(), 0);
  using C = const VtkContact&;
  xml.open("CellData");
  xml.array("normal_force", 1, gather(contacts, [](C c) { return c.normal.dot(c.normal_force); }));
  xml.array("tangential_force", 1, gather(contacts, [](C c) { return c.tangential_force.norm(); }));
  xml.array("status", 1, gather(contacts, [](C c) { return static_cast<std::int32_t>(c.status); }));
  xml.array("body_a", 1, gather(contacts, [](C c) { return static_cast<std::int32_t>(c.body_a); }));
  xml.array("body_b", 1, gather(contacts, [](C c) { return static_cast<std::int32_t>(c.body_b); }));
  xml.close("CellData");
  points(xml, pts);
  cells(xml, "Lines", lines);
  write_file_atomic(path, xml.finish());
}

void write_container_vtp(const std::string& path, const ContainerMesh& mesh, const std::vector<Vec3>& normal,
                         const std::vector<double>& normal_force, const VtkTime& time, VtkEncoding encoding) {
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
  VtkXml xml(encoding, time, mesh.points.size(), 0, 0, polys.size());
  xml.open("CellData");
  xml.array("wall_index", 1, gather(mesh.wall, [](int w) { return static_cast<std::int32_t>(w); }));
  xml.array("side_id", 1, gather(mesh.wall, [](int w) { return static_cast<std::int32_t>(wall_side(w)); }));
  xml.array("normal", 3, gather(normal, [](const Vec3& v) { return v; }));
  xml.array("normal_force", 1, normal_force);
  xml.close("CellData");
  points(xml, mesh.points);
  cells(xml, "Polys", polys);
  write_file_atomic(path, xml.finish());
}

}  // namespace ratchet

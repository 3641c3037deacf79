#include "ratchet/geometry/particle_generator.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ratchet {

PolyhedronBuild generate_ellipsoid_particle(const EllipsoidParticleSpec& spec, Rng& rng,
                                            double* radius_out, int* redrawn) {
  if (spec.vertices < 4)
    throw std::invalid_argument("ellipsoid particle: need at least 4 vertices, got " +
                                std::to_string(spec.vertices));
  if (!(std::isfinite(spec.radius_min) && std::isfinite(spec.radius_max) && spec.radius_min > 0.0 &&
        spec.radius_min <= spec.radius_max))
    throw std::invalid_argument("ellipsoid particle: expected finite 0 < radius_min <= radius_max");
  if (!spec.axes.allFinite() || !(spec.axes.minCoeff() > 0.0))
    throw std::invalid_argument("ellipsoid particle: axes must be positive and finite");

  for (int attempt = 0; attempt <= kMaxRedraws; ++attempt) {
    // Fixed draw order (radius, then one direction per vertex) keeps particles a
    // function of the seed alone.
    const double r = uniform(rng, spec.radius_min, spec.radius_max);
    const double scale = r / spec.axes.maxCoeff();  // largest semi-axis is r
    std::vector<Vec3> points;
    points.reserve(static_cast<std::size_t>(spec.vertices));
    for (int i = 0; i < spec.vertices; ++i)
      points.push_back(scale * spec.axes.cwiseProduct(uniform_unit_vector(rng)));
    // A sliver (few vertices, nearly coplanar) is a plate the contact method and the
    // time step cannot handle: drawn again, from the next numbers of the same stream.
    if (point_cloud_defect(points).empty()) {
      PolyhedronBuild build = build_convex_polyhedron(points, "ellipsoid particle");
      if (build.shape.min_face_offset >= kMinInradius * r) {
        if (radius_out != nullptr) *radius_out = r;
        if (redrawn != nullptr) *redrawn += attempt;
        return build;
      }
    }
  }
  throw std::invalid_argument("ellipsoid particle: " + std::to_string(kMaxRedraws + 1) + " draws of " +
                              std::to_string(spec.vertices) + " vertices in a row gave slivers (inradius below " +
                              std::to_string(kMinInradius) + " r): use more vertices");
}

}  // namespace ratchet

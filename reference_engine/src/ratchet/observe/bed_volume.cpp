#include "ratchet/observe/bed_volume.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace ratchet {
namespace {

// Relative thickness below which the cloud counts as flat (same threshold as
// geometry/convex_polyhedron.cpp): Qhull's roundoff handling is unreliable there and
// the volume would be noise.
constexpr double kFlatTolerance = 1e-9;

[[noreturn]] void fail(const std::string& why) { throw std::invalid_argument("convex_hull_volume: " + why); }

// Rejects clouds without a solid hull: greedy extreme-point simplex, distances
// relative to the cloud size.
void validate(const std::vector<Vec3>& points) {
  if (points.size() < 4) fail("need at least 4 points, got " + std::to_string(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) fail("point " + std::to_string(i) + " is not finite");
  const Vec3& p0 = points[0];
  double d1 = 0.0;
  Vec3 p1 = p0;
  for (const Vec3& p : points)
    if ((p - p0).norm() > d1) d1 = (p - p0).norm(), p1 = p;
  if (!(d1 > 0.0)) fail("all points coincide");
  const Vec3 axis = (p1 - p0) / d1;
  double d2 = 0.0;
  Vec3 p2 = p0;
  for (const Vec3& p : points) {
    const double d = (p - p0).cross(axis).norm();
    if (d > d2) d2 = d, p2 = p;
  }
  if (d2 <= kFlatTolerance * d1) fail("points are collinear");
  const Vec3 normal = (p1 - p0).cross(p2 - p0).normalized();
  double d3 = 0.0;
  for (const Vec3& p : points) d3 = std::max(d3, std::abs((p - p0).dot(normal)));
  if (d3 <= kFlatTolerance * d1) fail("points are coplanar");
}

// One Qhull run with its messages sent to `err`; returns Qhull's exit code and the
// total volume in `volume`.
int run_qhull(std::vector<coordT>& coords, int n, FILE* err, double& volume) {
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, err);
  char options[] = "qhull FA";  // 'FA': compute total area and volume (qh_getarea)
  const int code = qh_new_qhull(qh, 3, n, coords.data(), False, options, nullptr, err);
  if (code == qh_ERRnone) {
    if (!qh->hasAreaVolume) qh_getarea(qh, qh->facet_list);
    volume = qh->totvol;
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (curlong != 0 || totlong != 0)
    throw std::runtime_error("convex_hull_volume: Qhull did not free " + std::to_string(totlong) + " bytes");
  return code;
}

}  // namespace

double convex_hull_volume(const std::vector<Vec3>& points) {
  validate(points);
  // Centred coordinates: the volume is translation invariant, and centring limits
  // cancellation for a bed far from the origin.
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  std::vector<coordT> coords(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + static_cast<std::size_t>(k)] = points[i][k] - mean[k];
  const int n = static_cast<int>(points.size());

  // Qhull stays silent: messages go to /dev/null; only a failed run is repeated into
  // a memory stream to put Qhull's diagnostics into the exception.
  static FILE* const null_stream = std::fopen("/dev/null", "w");
  double volume = 0.0;
  if (null_stream != nullptr && run_qhull(coords, n, null_stream, volume) == qh_ERRnone) return volume;

  char* text = nullptr;
  std::size_t size = 0;
  FILE* err = open_memstream(&text, &size);
  if (err == nullptr) throw std::runtime_error("convex_hull_volume: cannot open a stream for Qhull's messages");
  const int code = run_qhull(coords, n, err, volume);
  std::fclose(err);
  const std::string message = text ? text : "";
  std::free(text);
  if (code == qh_ERRnone) return volume;
  const std::string why = "Qhull failed (code " + std::to_string(code) + "): " + message;
  if (code == qh_ERRsingular || code == qh_ERRprec || code == qh_ERRinput) fail(why);
  throw std::runtime_error("convex_hull_volume: " + why);
}

}  // namespace ratchet

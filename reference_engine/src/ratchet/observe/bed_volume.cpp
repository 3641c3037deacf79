#include "ratchet/observe/bed_volume.hpp"

#include "ratchet/geometry/convex_polyhedron.hpp"
#include "ratchet/observe/bed_geometry.hpp"

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

[[noreturn]] void fail(const std::string& why) { throw std::invalid_argument("convex_hull_volume: " + why); }

// Rejects clouds without a solid hull (geometry/convex_polyhedron.hpp): below the flat
// threshold Qhull's roundoff handling is unreliable and the volume would be noise.
void validate(const std::vector<Vec3>& points) {
  const std::string why = point_cloud_defect(points);
  if (!why.empty()) fail(why);
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

double bed_volume(const SceneDef& scene, const State& state) { return convex_hull_volume(bed_points(scene, state)); }

}  // namespace ratchet

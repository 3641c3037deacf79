#include "ratchet/core/random.hpp"

#include <cmath>

namespace ratchet {

Vec3 uniform_unit_vector(Rng& rng) {
  const double z = uniform(rng, -1.0, 1.0);
  const double phi = uniform(rng, 0.0, 2.0 * M_PI);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

Quat uniform_rotation(Rng& rng) {
  const double u1 = uniform01(rng), u2 = uniform01(rng), u3 = uniform01(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  Quat q(b * std::cos(2.0 * M_PI * u3),   // w
         a * std::sin(2.0 * M_PI * u2),   // x
         a * std::cos(2.0 * M_PI * u2),   // y
         b * std::sin(2.0 * M_PI * u3));  // z
  return q.normalized();
}

}  // namespace ratchet

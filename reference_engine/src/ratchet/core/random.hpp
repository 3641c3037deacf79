// Pinned random numbers: std::mt19937_64 with an explicit seed, and mappings to
// doubles written out here so they do not depend on the standard library's
// distribution implementations (docs/method.md, determinism).
#pragma once

#include <cstdint>
#include <random>

#include "ratchet/core/types.hpp"

namespace ratchet {

using Rng = std::mt19937_64;

// Uniform double in [0, 1) from the top 53 bits.
inline double uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

inline double uniform(Rng& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }

// Uniform direction on the unit sphere (Archimedes: z uniform in [-1, 1]).
Vec3 uniform_unit_vector(Rng& rng);

// Uniform random rotation (Shoemake 1992, "Uniform random rotations", Graphics Gems III).
Quat uniform_rotation(Rng& rng);

}  // namespace ratchet

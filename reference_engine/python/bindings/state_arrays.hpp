// The state's per-body vectors as numpy arrays that share the engine's memory (no copy):
// std::vector<Vec3> and std::vector<Quat> are contiguous doubles, 3 or 4 per body.
// Read-only, so what Python sees is always what the engine stepped.
#pragma once

#include <vector>

#include <pybind11/numpy.h>

#include "ratchet/core/types.hpp"

namespace ratchet_python {

// (N, 3) view of `v`; `owner` (the Python World) is kept alive by the array.
pybind11::array vec3_view(const std::vector<ratchet::Vec3>& v, pybind11::handle owner);

// (N, 4) view of `q` in Eigen's storage order (x, y, z, w): scalar last, as
// scipy.spatial.transform.Rotation.from_quat takes it.
pybind11::array quat_view(const std::vector<ratchet::Quat>& q, pybind11::handle owner);

}  // namespace ratchet_python

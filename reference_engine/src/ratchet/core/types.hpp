// Basic numeric types of the engine. Everything is double precision (determinism
// contract, docs/method.md); Eigen supplies the small fixed-size algebra.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ratchet {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;  // unit quaternion, body -> world

// Index of a body in the state arrays. Walls are not bodies (see world/state.hpp).
using BodyId = int;

}  // namespace ratchet

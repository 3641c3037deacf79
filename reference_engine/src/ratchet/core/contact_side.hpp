// The second side of a contact is one int: a body index (>= 0) or a container wall.
// Walls are stored as -1 - w so that body indices keep their natural range; these three
// helpers are the only place that encoding is spelt out.
#pragma once

namespace ratchet {

constexpr int wall_side(int wall) { return -1 - wall; }    // wall index -> side id
constexpr bool is_wall(int side) { return side < 0; }      // side id names a wall
constexpr int wall_index(int side) { return -1 - side; }   // side id -> wall index

}  // namespace ratchet

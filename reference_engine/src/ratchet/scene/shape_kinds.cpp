#include "ratchet/scene/shape_kinds.hpp"

#include <array>

namespace ratchet {

const ShapeKindFacts& shape_kind(ShapeKind k) {
  // In the order of ShapeKind; a kind added there without its entry fails to compile.
  static const std::array<const ShapeKindFacts*, static_cast<std::size_t>(ShapeKind::Count)> kinds = {
      &sphere_kind(), &polyhedron_kind()};
  return *kinds[static_cast<std::size_t>(k)];
}

}  // namespace ratchet

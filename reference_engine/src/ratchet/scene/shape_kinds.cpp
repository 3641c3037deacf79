#include "ratchet/scene/shape_kinds.hpp"

#include <cstddef>

namespace ratchet {

const ShapeKindFacts& shape_kind(ShapeKind k) {
  // In the order of ShapeKind. Sized by its entries, not by Count: a std::array of Count
  // would take a missing entry as a null pointer and compile.
  static const ShapeKindFacts* const kinds[] = {&sphere_kind(), &polyhedron_kind()};
  static_assert(sizeof kinds / sizeof kinds[0] == static_cast<std::size_t>(ShapeKind::Count),
                "every ShapeKind needs its facts");
  return *kinds[static_cast<std::size_t>(k)];
}

}  // namespace ratchet

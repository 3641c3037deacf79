#include "ratchet/world/test_hooks.hpp"

namespace ratchet {

TestHooks& test_hooks() {
  static TestHooks hooks;
  return hooks;
}

}  // namespace ratchet

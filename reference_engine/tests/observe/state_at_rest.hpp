// Test helper: the state of a scene's bodies at their initial poses, at rest.
#pragma once

#include "ratchet/scene/scene.hpp"
#include "ratchet/world/state.hpp"

namespace ratchet::test {

inline State state_at_rest(const SceneDef& s) {
  State st;
  for (const BodyDef& b : s.bodies) {
    st.x.push_back(b.position);
    st.q.push_back(b.orientation);
    st.v.push_back(Vec3::Zero());
    st.w.push_back(Vec3::Zero());
  }
  return st;
}

}  // namespace ratchet::test

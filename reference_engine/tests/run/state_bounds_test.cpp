// unphysical_state on a bed large enough for its parallel look (more than 256 bodies):
// the same verdict and the same text on 1, 2, 3 and 8 threads, for a state within the
// bounds, a body outside the container and a body faster than its size per step.
#include "ratchet/run/state_bounds.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <string>
#include <vector>

#include "ratchet/scene/scene.hpp"

namespace ratchet {
namespace {

using nlohmann::json;

// 20 x 20 spheres of radius 0.5 resting on the floor plane; `change` edits body 317.
SceneDef grid_bed(const json& change) {
  json bodies = json::array();
  for (int i = 0; i < 400; ++i) {
    json b = {{"shape", "sphere"}, {"radius", 0.5}, {"position", {1.5 * (i % 20), 1.5 * (i / 20), 0.5}}};
    if (i == 317) b.update(change);
    bodies.push_back(b);
  }
  json scene = {{"name", "grid"}, {"time", {{"dt", 0.1}, {"duration", 1.0}}},
                {"container", {{"type", "planes"}, {"planes", {{{"normal", {0, 0, 1}}, {"point", {0, 0, 0}}}}}}},
                {"particles", {{"bodies", bodies}}}};
  return build_scene(scene, "grid.json");
}

std::vector<std::string> on_each_thread_count(const SceneDef& scene) {
  const int saved = omp_get_max_threads();
  std::vector<std::string> said;
  for (int threads : {1, 2, 3, 8}) {
    omp_set_num_threads(threads);
    const World world(scene);
    said.push_back(unphysical_state(world));
  }
  omp_set_num_threads(saved);
  return said;
}

TEST(StateBounds, ALargeBedGetsTheSameVerdictOnAnyNumberOfThreads) {
  for (const std::string& s : on_each_thread_count(grid_bed(json::object()))) EXPECT_EQ(s, "");
  const std::vector<std::string> outside = on_each_thread_count(grid_bed({{"position", {0, 0, -5}}}));
  EXPECT_NE(outside[0].find("1 body outside the container: body 317 (centre 5 behind wall 0, size 0.5)"),
            std::string::npos)
      << outside[0];
  const std::vector<std::string> thrown = on_each_thread_count(grid_bed({{"velocity", {600, 0, 0}}}));
  EXPECT_NE(thrown[0].find("body 317 moved 60 in one step"), std::string::npos) << thrown[0];
  for (std::size_t k = 1; k < outside.size(); ++k) {
    EXPECT_EQ(outside[k], outside[0]) << "thread count index " << k;
    EXPECT_EQ(thrown[k], thrown[0]) << "thread count index " << k;
  }
}

}  // namespace
}  // namespace ratchet

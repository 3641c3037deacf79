// Hard cases: scenes that push the method past its comfortable range, each with the
// bound it must keep and why (docs/validation.md, "Hard cases").
//   1. Deep initial overlap: a unit cube placed 0.4 into another one on the floor. The
//      gap relaxation removes the overlap; the energy it gives the cube is at most
//      m g delta (the separation speed is capped at sqrt(2 g delta), docs/method.md
//      s. 5), for every time step. Uncapped, the cube left at p_gap delta / h: 10 at
//      h = 0.004, 40 at h = 0.001, and flew tens of units high.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "ratchet/observe/energy.hpp"
#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"
#include "support/check_record.hpp"

namespace ratchet {
namespace {

constexpr double kDelta = 0.4;  // initial overlap of the two unit cubes

struct Watched {
  double ke_max = 0.0;      // kinetic energy, largest over the run
  double top_max = 0.0;     // highest centre of the upper cube
  double overlap_end = 0.0; // deepest overlap at the end
};

Watched drop_overlapping_cubes(double h, bool rotation, double compliance) {
  const nlohmann::json scene = {
      {"name", "deep_overlap"},
      {"time", {{"dt", h}, {"duration", 4.0}}},
      {"solver", {{"compliance", compliance}}},
      {"effects", {{"rotation", rotation}}},
      {"container", {{"type", "planes"}, {"planes", {{{"normal", {0, 0, 1}}, {"point", {0, 0, 0}}}}}}},
      {"particles",
       {{"bodies",
         {{{"shape", "box"}, {"half_extents", {0.5, 0.5, 0.5}}, {"position", {0, 0, 0.5}}},
          {{"shape", "box"}, {"half_extents", {0.5, 0.5, 0.5}}, {"position", {0, 0, 1.0 - kDelta + 0.5}}}}}}},
      {"outputs", {{"volume", false}}}};
  World world(build_scene(scene, "deep_overlap.json"));
  Watched w;
  run_world(world, {}, [&](const World& wd) {
    w.ke_max = std::max(w.ke_max, kinetic_energy(wd.scene(), wd.state()));
    w.top_max = std::max(w.top_max, wd.state().x[1].z());
    w.overlap_end = wd.stats().max_overlap;
  });
  return w;
}

class DeepOverlap : public ::testing::TestWithParam<double> {};

TEST_P(DeepOverlap, SeparatesWithEnergyBoundedByTheOverlap) {
  const double h = GetParam();
  const std::string name = "deep_overlap_h" + validation::format_number(h);
  // m = 1 (unit cube, density 1), g = 1: the bound m g delta. The cap holds the
  // separation speed to sqrt(2 g delta) exactly; gravity only takes energy away.
  const double bound = 1.0 * 1.0 * kDelta;
  // Rigid, and compliant as the standard and paper tiers (the cap is a second law there).
  for (const auto& [rotation, compliance] : {std::pair{false, 0.0}, std::pair{true, 0.0}, std::pair{true, 0.1}}) {
    const Watched w = drop_overlapping_cubes(h, rotation, compliance);
    const std::string tag = std::string(rotation ? ", rotation on" : ", rotation off") +
                            (compliance > 0.0 ? ", compliance " + validation::format_number(compliance) : "");
    // Compliant, the push also compresses the lower cube's floor contact, whose own
    // correction may add up to m g margin (margin 0.05, the default).
    const double limit = compliance > 0.0 ? bound + 1.0 * 1.0 * 0.05 : bound * (1.0 + 1e-9);
    EXPECT_TRUE(validation::check_le(name, "max kinetic energy" + tag, w.ke_max, limit,
                                     "separation speed capped at sqrt(2 g* max(delta, margin)): at most m g "
                                     "delta per overlap, any h (uncapped: (p_gap delta / h)^2 / 2 = 50 at "
                                     "h = 0.004, 800 at 0.001); compliant, plus m g margin for the floor contact "
                                     "the push compresses"));
    // Lifted by the overlap, then at most delta more by the speed it leaves with.
    EXPECT_TRUE(validation::check_le(name, "highest centre of the upper cube" + tag, w.top_max,
                                     1.5 - kDelta + 2.0 * kDelta + 1e-6,
                                     "energy m g delta lifts the cube by delta after the overlap is gone"));
    EXPECT_TRUE(validation::check_le(name, "overlap after 4 time units" + tag, w.overlap_end, 0.01,
                                     "the relaxation keeps removing it at p_gap per step, capped speed or not; "
                                     "0.01 is the resting overlap scale of a box on a box"));
  }
}

INSTANTIATE_TEST_SUITE_P(TimeSteps, DeepOverlap, ::testing::Values(0.004, 0.001));

}  // namespace
}  // namespace ratchet

// Validation 3: a box on an incline, by tilting gravity by beta: g = (sin b, 0, -cos b).
// Coulomb: it sticks when tan(beta) < mu and slides with a = g (sin b - mu cos b) when
// tan(beta) > mu.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ratchet/run/runner.hpp"
#include "ratchet/scene/scene.hpp"
#include "ratchet/world/world.hpp"
#include "support/check_record.hpp"

namespace ratchet {
namespace {

struct InclineResult {
  double dx = 0.0;         // displacement along the slope
  double velocity = 0.0;   // final velocity along the slope
  double duration = 0.0;
  double max_tilt = 0.0;   // max |rotation angle| of the box (rocking)
};

InclineResult run_incline(double tan_beta, double mu) {
  const double beta = std::atan(tan_beta);
  char gravity[128];
  std::snprintf(gravity, sizeof gravity, "gravity=[%.17g, 0, %.17g]", std::sin(beta), -std::cos(beta));
  char friction[64];
  std::snprintf(friction, sizeof friction, "materials.wall_friction=%.17g", mu);
  const SceneDef scene =
      load_scene(std::string(RATCHET_VALIDATION_DIR) + "/incline/box.json", {gravity, friction});
  World world(scene);
  InclineResult r;
  run_world(world, {}, [&](const World& w) {
    const Eigen::AngleAxisd aa(w.state().q[0]);
    r.max_tilt = std::max(r.max_tilt, std::abs(aa.angle()));
  });
  r.dx = world.state().x[0].x() - scene.bodies[0].position.x();
  r.velocity = world.state().v[0].x();
  r.duration = world.state().t;
  return r;
}

TEST(BoxOnIncline, SticksBelowTheFrictionAngle) {
  const InclineResult r = run_incline(0.4, 0.5);
  EXPECT_TRUE(validation::check_near("incline tan(beta) = 0.4 < mu = 0.5", "displacement along the slope",
                                     r.dx, 0.0, 1e-9, "sticking contact: round-off only"));
  EXPECT_TRUE(validation::check_le("incline tan(beta) = 0.4 < mu = 0.5", "max rocking angle (rad)", r.max_tilt,
                                   1e-9, "4-point face contact resists rocking"));
}

TEST(BoxOnIncline, SlidesWithCoulombAcceleration) {
  const double tan_beta = 0.7, mu = 0.5, beta = std::atan(tan_beta);
  const InclineResult r = run_incline(tan_beta, mu);
  const double a = std::sin(beta) - mu * std::cos(beta);  // g = 1
  const std::string c = "incline tan(beta) = 0.7 > mu = 0.5";
  EXPECT_TRUE(validation::check_rel(c, "acceleration from the final velocity", r.velocity / r.duration, a, 0.01,
                                    "brief: 1 %"));
  EXPECT_TRUE(validation::check_rel(c, "acceleration from the displacement (x = a t^2 / 2)",
                                    2.0 * r.dx / (r.duration * r.duration), a, 0.01,
                                    "brief: 1 %; the implicit scheme's O(h) offset is 0.05 % here"));
  EXPECT_TRUE(validation::check_le(c, "max rocking angle (rad)", r.max_tilt, 1e-6,
                                   "no tipping: the tipping angle is far above beta"));
}

}  // namespace
}  // namespace ratchet

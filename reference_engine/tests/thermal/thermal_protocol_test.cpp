#include "ratchet/thermal/thermal_protocol.hpp"

#include <gtest/gtest.h>

namespace ratchet {
namespace {

ThermalProtocol protocol() {
  ThermalProtocol p;
  p.enabled = true;
  p.T0 = 10.0;
  p.T1 = 110.0;
  p.start_time = 1.0;
  p.heat_time = 4.0;
  p.hold_time = 2.0;
  p.cool_time = 8.0;
  p.cycles = 2;
  p.alpha_p = 1e-4;
  p.alpha_c = 1e-3;
  return p;
}

TEST(ThermalProtocol, TemperatureFollowsHeatHoldCoolHold) {
  const ThermalProtocol p = protocol();  // cycle: [0,4) heat, [4,6) hold, [6,14) cool, [14,16) hold
  EXPECT_DOUBLE_EQ(temperature(p, 0.5), 10.0);   // before start_time
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 2.0), 60.0);
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 5.0), 110.0);
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 10.0), 60.0);
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 15.0), 10.0);
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 16.0 + 1.0), 35.0);  // second cycle
  EXPECT_DOUBLE_EQ(temperature(p, 1.0 + 40.0), 10.0);        // after the last cycle
  EXPECT_EQ(cycle_index(p, 1.0 + 17.0), 1);
  EXPECT_EQ(cycle_index(p, 100.0), 2);
}

TEST(ThermalProtocol, ScalesOnlyForTheEffectsAskedFor) {
  const ThermalProtocol p = protocol();
  Effects e;
  ThermalScales s = thermal_scales(p, e, 1.0 + 5.0);
  EXPECT_DOUBLE_EQ(s.s_p, 1.0 + 1e-4 * 100.0);
  EXPECT_DOUBLE_EQ(s.s_c, 1.0 + 1e-3 * 100.0);
  e.container_expansion = false;
  s = thermal_scales(p, e, 1.0 + 5.0);
  EXPECT_DOUBLE_EQ(s.s_c, 1.0);
  EXPECT_DOUBLE_EQ(s.s_p, 1.01);
}

}  // namespace
}  // namespace ratchet

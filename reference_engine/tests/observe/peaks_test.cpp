#include "ratchet/observe/peaks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace ratchet {
namespace {

TEST(CyclePeaks, SineWithGrowingAmplitudeHasOneKnownPeakPerCycle) {
  // s(t) = (1 + k) sin(2 pi (t - t0) / L) in cycle k: maximum 1 + k at t0 + k L + L/4.
  // Sampled at step L/400 so that L/4 is a sample.
  const double t0 = 2.0, L = 4.0, dt = L / 400.0;
  std::vector<double> t, s;
  for (int i = 0; i < 5 * 400; ++i) {
    const double ti = t0 + i * dt;
    t.push_back(ti);
    s.push_back((1.0 + i / 400) * std::sin(2.0 * M_PI * (ti - t0) / L));
  }
  const std::vector<CyclePeak> p = cycle_peaks(t, s, t0, L, 5);
  ASSERT_EQ(p.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const CyclePeak& q = p[static_cast<std::size_t>(k)];
    EXPECT_EQ(q.cycle, k);
    // 1e-12: sin at the sampled quarter period is 1 up to rounding of its argument.
    EXPECT_NEAR(q.value, 1.0 + k, 1e-12);
    // The sample time itself, t0 + (400 k + 100) dt; 1e-12 for the time arithmetic.
    EXPECT_NEAR(q.time, t0 + k * L + L / 4.0, 1e-12);
  }
}

TEST(CyclePeaks, TiesGoToTheEarliestSample) {
  const std::vector<double> t = {0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75};
  const std::vector<double> s = {1.0, 3.0, 3.0, 2.0, 5.0, 5.0, 5.0, 5.0};
  const std::vector<CyclePeak> p = cycle_peaks(t, s, 0.0, 1.0, 2);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].value, 3.0);
  EXPECT_EQ(p[0].time, 0.25);
  EXPECT_EQ(p[1].value, 5.0);
  EXPECT_EQ(p[1].time, 1.0);
  // Same data given in reverse order: still the earliest time.
  const std::vector<double> tr(t.rbegin(), t.rend()), sr(s.rbegin(), s.rend());
  const std::vector<CyclePeak> pr = cycle_peaks(tr, sr, 0.0, 1.0, 2);
  ASSERT_EQ(pr.size(), 2u);
  EXPECT_EQ(pr[0].time, 0.25);
  EXPECT_EQ(pr[1].time, 1.0);
}

TEST(CyclePeaks, MaximumAtTheWindowStartBelongsToThatWindow) {
  // Falling sawtooth: the largest sample of each window is its first, at start + k L.
  // The sample at start + (k+1) L (a window's end) opens the next window.
  const double start = 0.5, L = 2.0;
  std::vector<double> t, s;
  for (int i = 0; i <= 3 * 8; ++i) {
    const double ti = start + i * 0.25;
    t.push_back(ti);
    s.push_back(10.0 - (i % 8) + (i / 8));  // window k: 10 + k at its start, then falling
  }
  const std::vector<CyclePeak> p = cycle_peaks(t, s, start, L, 3);
  ASSERT_EQ(p.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(p[static_cast<std::size_t>(k)].time, start + k * L) << k;
    EXPECT_EQ(p[static_cast<std::size_t>(k)].value, 10.0 + k) << k;
  }
}

TEST(CyclePeaks, SamplesOutsideTheWindowsAndNaNAreIgnoredAndEmptyWindowsSkipped) {
  const std::vector<double> t = {-1.0, 0.1, 0.2, 2.5, 3.0, 9.0};
  const std::vector<double> s = {100.0, 1.0, std::nan(""), 2.0, 50.0, 100.0};
  // Windows [0,1), [1,2), [2,3): window 1 empty; t = 3 is past the last window.
  const std::vector<CyclePeak> p = cycle_peaks(t, s, 0.0, 1.0, 3);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].cycle, 0);
  EXPECT_EQ(p[0].value, 1.0);
  EXPECT_EQ(p[1].cycle, 2);
  EXPECT_EQ(p[1].value, 2.0);
}

TEST(CyclePeaks, RejectsBadInput) {
  EXPECT_THROW(cycle_peaks({0.0}, {}, 0.0, 1.0, 1), std::invalid_argument);
  EXPECT_THROW(cycle_peaks({0.0}, {1.0}, 0.0, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(cycle_peaks({0.0}, {1.0}, 0.0, 1.0, -1), std::invalid_argument);
  EXPECT_TRUE(cycle_peaks({0.0}, {1.0}, 0.0, 1.0, 0).empty());
}

TEST(MeanPeak, MeanAndSampleStddevOverTheWindow) {
  std::vector<CyclePeak> p;
  for (int k = 0; k < 6; ++k) p.push_back({k, 10.0 * k, k + 0.5});
  // Cycles 2..4: values 20, 30, 40 -> mean 30, sample variance (100 + 0 + 100) / 2 = 100.
  const MeanPeak m = mean_peak(p, 2, 4);
  EXPECT_EQ(m.count, 3);
  EXPECT_EQ(m.first_cycle, 2);
  EXPECT_EQ(m.last_cycle, 4);
  // 1e-12: exact in binary but for the division and square root.
  EXPECT_NEAR(m.mean, 30.0, 1e-12);
  EXPECT_NEAR(m.stddev, 10.0, 1e-12);
}

TEST(MeanPeak, SkippedCyclesAndEdgeCases) {
  const std::vector<CyclePeak> p = {{0, 1.0, 0.0}, {2, 3.0, 2.0}, {3, 5.0, 3.0}};
  const MeanPeak m = mean_peak(p, 1, 3);  // cycle 1 missing
  EXPECT_EQ(m.count, 2);
  EXPECT_NEAR(m.mean, 4.0, 1e-12);  // 1e-12: rounding only
  EXPECT_NEAR(m.stddev, std::sqrt(2.0), 1e-12);
  const MeanPeak one = mean_peak(p, 3, 3);
  EXPECT_EQ(one.count, 1);
  EXPECT_EQ(one.mean, 5.0);
  EXPECT_TRUE(std::isnan(one.stddev));
  const MeanPeak none = mean_peak(p, 5, 9);
  EXPECT_EQ(none.count, 0);
  EXPECT_TRUE(std::isnan(none.mean));
  EXPECT_THROW(mean_peak(p, 3, 2), std::invalid_argument);
}

}  // namespace
}  // namespace ratchet
